#!/usr/bin/env python3
"""The haptic bridge (docs/haptic-protocol.md) with the example client examples/haptic/haptic_client.py:
`needlesim serve --haptic-port 0` on a realtime2d scenario, an insertion and retraction at 1 kHz,
forces that rise on insertion and reverse on retraction, a wrong version, size, a non-finite
pose and undefined flag bits refused with error packets, and the round-trip latency percentiles (printed).

usage: haptic_bridge_test.py NEEDLESIM SCENARIO SOURCE_DIR [CXX_CLIENT]
"""
import math
import os
import struct
import subprocess
import sys
import time

needlesim, scenario, source = sys.argv[1:4]
cxx_client = sys.argv[4] if len(sys.argv) > 4 else None
sys.path.insert(0, os.path.join(source, 'examples', 'haptic'))
import haptic_client as hc  # noqa: E402


def start_server():
    proc = subprocess.Popen([needlesim, 'serve', scenario, '--port', '0', '--haptic-port', '0'],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    end = time.time() + 20
    while time.time() < end:
        line = proc.stdout.readline()
        if line.startswith('haptic bridge: udp://'):
            return proc, int(line.split(':')[-1].split()[0])
        if not line:
            break
    proc.kill()
    raise AssertionError('needlesim serve printed no haptic port')


def check_refusals(client):
    for version in (0, 2):
        try:
            client.exchange(depth=0.0, version=version)
            raise AssertionError(f'version {version} was not refused')
        except hc.HapticError as e:
            assert e.code == 1 and 'version' in str(e), e
    try:
        client.exchange(depth=math.nan)
        raise AssertionError('a NaN pose was not refused')
    except hc.HapticError as e:
        assert e.code == 4, e
    for flags in (2, 0x80000001):  # undefined flag bits (only bit 0, reset, is defined)
        client.sock.sendto(hc.POSE_PACKET.pack(hc.MAGIC, hc.VERSION, hc.POSE, 101, flags, 0, 0.0, 0.0, 0.0, 0.0, 0.0),
                           client.address)
        data, _ = client.sock.recvfrom(512)
        kind, sequence, code = struct.unpack_from('<HII', data, 6)
        assert (kind, sequence, code) == (hc.ERROR, 101, 4), (flags, kind, sequence, code)
    client.sock.sendto(struct.pack('<IHHI', hc.MAGIC, hc.VERSION, hc.POSE, 99), client.address)  # 12 bytes: no header
    client.sock.sendto(struct.pack('<IHHI4x', hc.MAGIC, hc.VERSION, hc.POSE, 100), client.address)  # 16 bytes: wrong size
    data, _ = client.sock.recvfrom(512)
    kind, sequence, code = struct.unpack_from('<HII', data, 6)
    assert (kind, sequence, code) == (hc.ERROR, 100, 2), (kind, sequence, code)
    print('refused: versions 0 and 2 (code 1), a NaN pose and undefined flag bits (code 4), a short packet (code 2)')


def check_forces(poses, states):
    deepest = max(range(len(poses)), key=lambda i: poses[i])
    going_in = [s for p, s in zip(poses[:deepest], states[:deepest]) if p > 0.01]
    axial = [s['axial_force'] for s in going_in]
    assert axial[-1] > 0.05 and axial[-1] > axial[0], f'the force rises on insertion: {axial[0]:.3f} -> {axial[-1]:.3f} N'
    assert all(math.isclose(s['force'][0], -s['axial_force']) for s in states), 'force x is minus the axial force'
    assert any(s['phase'] in ('cutting', 'inside') for s in states), 'the needle punctured'
    late = states[deepest + (len(states) - deepest) // 2:]
    assert min(s['friction_force'] for s in late) < 0, 'friction reverses on retraction'
    print(f'axial force {axial[0]:.3f} N at 10 mm -> {axial[-1]:.3f} N at {poses[deepest] * 1e3:.0f} mm; '
          f'friction on the way out down to {min(s["friction_force"] for s in late):.3f} N')


def main():
    server, port = start_server()
    try:
        client = hc.HapticClient('127.0.0.1', port)
        check_refusals(client)
        poses, states, rtts = hc.insertion(client, depth=0.03, seconds=3.0)
        check_forces(poses, states)
        ages = [s['state_age'] for s in states]
        print(f'python client: {len(rtts)} poses at 1 kHz, round trip p50 {hc.percentile(rtts, 50) * 1e6:.0f} us, '
              f'p99 {hc.percentile(rtts, 99) * 1e6:.0f} us; state age p50 {hc.percentile(ages, 50) * 1e6:.0f} us')
        assert hc.percentile(rtts, 50) < 0.005, 'the median round trip stays under 5 ms'
        if cxx_client:
            out = subprocess.run([cxx_client, '--port', str(port), '--seconds', '1.5'], capture_output=True, text=True, timeout=30)
            print('c++ client:', out.stdout.strip().replace('\n', '; '))
            assert out.returncode == 0, out.stderr
        server.send_signal(2)  # Ctrl-C
        assert server.wait(timeout=10) == 0, 'needlesim serve stops cleanly on Ctrl-C'
        print(server.stdout.read().strip().splitlines()[-1])
    finally:
        if server.poll() is None:
            server.kill()


main()
