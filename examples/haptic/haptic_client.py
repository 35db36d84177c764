#!/usr/bin/env python3
"""A haptic device's side of needlesim's haptic bridge (docs/haptic-protocol.md, version 1).

Start the server with `needlesim serve scenario.yaml --haptic-port 5700`, then
    python3 haptic_client.py --port 5700 --depth 0.03 --seconds 4
sends a pose at 1 kHz (insert to --depth and back out), receives the force on the hand for
each, and prints the force at depth and the round-trip latency percentiles. A device SDK
(OpenHaptics, libnifalcon) would send the stylus pose in place of the ramp and render the
force it gets back. Needs only the Python standard library.
"""
import argparse
import socket
import struct
import time

MAGIC = 0x5048534E  # bytes 'N' 'S' 'H' 'P'
VERSION = 1
POSE, STATE, ERROR = 1, 2, 3
# little-endian: magic, version, type, sequence, then the packet's own fields
POSE_PACKET = struct.Struct('<IHHIIQ5d')          # flags, client_time_ns, depth lateral rotation tilt roll
STATE_PACKET = struct.Struct('<IHHIIQQ2d3d3d4d')  # phase, client_time_ns, step, time depth, force[3], torque[3],
                                                   # axial_force friction_force tip_deflection state_age
ERROR_PACKET = struct.Struct('<IHHIIQ56s')        # code, client_time_ns, message
PHASES = ('outside', 'pressing', 'cutting', 'inside', 'through')
assert (POSE_PACKET.size, STATE_PACKET.size, ERROR_PACKET.size) == (64, 128, 80)


class HapticError(RuntimeError):
    """The server refused a packet (code and message of its error packet)."""

    def __init__(self, code, message):
        super().__init__(f'error {code}: {message}')
        self.code = code


class HapticClient:
    def __init__(self, host='127.0.0.1', port=5700, timeout=0.5):
        self.address = (host, port)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
        self.sock.settimeout(timeout)
        self.sequence = 0

    def exchange(self, depth=0.0, lateral=0.0, rotation=0.0, tilt=0.0, roll=0.0, reset=False, version=VERSION):
        """Sends one pose; returns (state dict, round-trip seconds). HapticError when refused."""
        self.sequence += 1
        sent = time.perf_counter_ns()
        packet = POSE_PACKET.pack(MAGIC, version, POSE, self.sequence, 1 if reset else 0, sent,
                                  depth, lateral, rotation, tilt, roll)
        self.sock.sendto(packet, self.address)
        while True:
            data, _ = self.sock.recvfrom(512)
            rtt = (time.perf_counter_ns() - sent) * 1e-9
            kind = struct.unpack_from('<H', data, 6)[0]
            sequence = struct.unpack_from('<I', data, 8)[0]
            if sequence != self.sequence:
                continue  # a late answer to an earlier pose
            if kind == ERROR:
                _, _, _, _, code, _, message = ERROR_PACKET.unpack(data)
                raise HapticError(code, message.split(b'\0')[0].decode('utf-8', 'replace'))
            return parse_state(data), rtt

    def close(self):
        self.sock.close()


def parse_state(data):
    v = STATE_PACKET.unpack(data)
    return {'sequence': v[3], 'phase': PHASES[v[4]] if v[4] < len(PHASES) else str(v[4]), 'step': v[6],
            'time': v[7], 'depth': v[8], 'force': v[9:12], 'torque': v[12:15], 'axial_force': v[15],
            'friction_force': v[16], 'tip_deflection': v[17], 'state_age': v[18]}


def insertion(client, depth, seconds, rate=1000.0):
    """Insert to `depth` [m] and back out over `seconds` at `rate` Hz: (poses, states, round trips)."""
    period, steps = 1.0 / rate, int(seconds * rate)
    poses, states, rtts = [], [], []
    start = time.perf_counter()
    for i in range(steps):
        phase = i / max(steps - 1, 1)
        d = depth * (2 * phase if phase < 0.5 else 2 * (1 - phase))
        state, rtt = client.exchange(depth=d)
        poses.append(d)
        states.append(state)
        rtts.append(rtt)
        pause = start + (i + 1) * period - time.perf_counter()
        if pause > 0:
            time.sleep(pause)
    return poses, states, rtts


def percentile(values, p):
    s = sorted(values)
    return s[min(len(s) - 1, int(round(p / 100 * (len(s) - 1))))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--host', default='127.0.0.1')
    ap.add_argument('--port', type=int, default=5700)
    ap.add_argument('--depth', type=float, default=0.03, help='deepest commanded depth [m]')
    ap.add_argument('--seconds', type=float, default=4.0)
    ap.add_argument('--rate', type=float, default=1000.0, help='poses per second')
    args = ap.parse_args()
    client = HapticClient(args.host, args.port)
    _, states, rtts = insertion(client, args.depth, args.seconds, args.rate)
    peak = max(states, key=lambda s: s['axial_force'])
    print(f'{len(rtts)} poses at {args.rate:.0f} Hz; peak axial force {peak["axial_force"]:.3f} N '
          f'at depth {peak["depth"] * 1e3:.2f} mm ({peak["phase"]})')
    print(f'round trip: p50 {percentile(rtts, 50) * 1e6:.0f} us, p99 {percentile(rtts, 99) * 1e6:.0f} us, '
          f'max {max(rtts) * 1e6:.0f} us')
    client.close()


if __name__ == '__main__':
    main()
