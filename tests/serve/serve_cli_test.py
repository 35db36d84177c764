#!/usr/bin/env python3
"""`needlesim serve` and `needlesim replay` on the command line (docs/serve.md).

A recorded session driven through the page's API (POST /api/drive, /api/reset, /api/stop) is
written as a complete results folder with its resets, `needlesim replay` reproduces its
forces.csv; requests with unknown fields or values of the wrong type are answered 400 naming
the field; the page's scripts keep their licence notices; the page answers within 100 ms while 64 idle or half-open connections are held; a
second SIGTERM while stopping still writes the recording; a --host beyond this machine is
warned about; a port in use, a bad host, a scenario that cannot be stepped live, a --record
target that is no results folder and a replay of a folder that is no recording each end with a
message and exit code 2, never a hang. Network use: 127.0.0.1 only.

usage: serve_cli_test.py NEEDLESIM SOURCE_DIR WORKDIR
"""
import csv
import json
import os
import shutil
import socket
import subprocess
import signal
import statistics
import sys
import threading
import time
import urllib.error
import urllib.request

needlesim, source, work = sys.argv[1:4]
scenario = os.path.join(source, 'examples', 'realtime2d', 'thesis_gelatin_18G_3mms.yaml')
shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)


def post(url, path, body):
    req = urllib.request.Request(url + path, data=json.dumps(body).encode(), method='POST',
                                 headers={'Content-Type': 'application/json'})
    return json.load(urllib.request.urlopen(req, timeout=10))


def post_error(url, path, body):
    """The status and JSON answer of a POST that is expected to be refused."""
    try:
        post(url, path, body)
    except urllib.error.HTTPError as e:
        return e.code, json.load(e)
    raise AssertionError(f'{path} {body} was taken')


def start(*args):
    proc = subprocess.Popen([needlesim, 'serve', *args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    end = time.time() + 20
    while time.time() < end:
        line = proc.stdout.readline()
        if line.startswith('trainer: '):
            return proc, line.split()[1].rstrip('/')
        if not line:
            break
    proc.kill()
    raise AssertionError('no URL from needlesim serve')


def record_and_replay():
    rec = os.path.join(work, 'session')
    proc, url = start(scenario, '--port', '0', '--record', rec, '--speed', '10')
    info = json.load(urllib.request.urlopen(url + '/api/info', timeout=10))
    assert info['engine'] == 'realtime2d' and info['record'] == rec, info
    for script in ('three.min.js', 'OrbitControls.js', 'chart.min.js'):  # each keeps its MIT notice
        head = urllib.request.urlopen(url + '/' + script, timeout=10).read(2000).decode()
        assert head.startswith('/*!') and 'MIT' in head, (script, head[:200])
    try:
        urllib.request.urlopen(urllib.request.Request(url + '/api/stop', data=b'', method='POST'), timeout=10)
        raise AssertionError('a POST that is not JSON was taken')
    except urllib.error.HTTPError as e:
        assert e.code == 415, e.code
    post(url, '/api/drive', {'insert': 1})
    time.sleep(1.5)
    post(url, '/api/drive', {'insert': -1})
    time.sleep(1.0)
    post(url, '/api/stop', {})
    out = proc.communicate(timeout=30)[0]
    assert proc.returncode == 0, out
    print(out.strip().splitlines()[-2])
    summary = json.load(open(os.path.join(rec, 'summary.json')))
    assert summary['status'] == 'complete', summary['status']
    for f in ('commands.csv', 'forces.csv', 'report.html'):
        assert f in summary['files'], summary['files']
    rows = list(csv.DictReader(open(os.path.join(rec, 'forces.csv'))))
    assert len(rows) > 1000 and summary['results']['puncture_depth']['value'] > 0, len(rows)
    assert not [n for n in os.listdir(work) if 'partial' in n], 'no staging folder is left'
    r = subprocess.run([needlesim, 'replay', rec, '--out', os.path.join(work, 'replayed')], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    print(r.stdout.strip())
    again = list(csv.DictReader(open(os.path.join(work, 'replayed', 'forces.csv'))))
    assert len(again) == len(rows)
    worst = max(abs(float(a['force_total [N]']) - float(b['force_total [N]'])) for a, b in zip(rows, again))
    assert worst < 1e-9, worst
    print(f'replayed forces.csv: {len(again)} rows, largest force difference {worst:.2g} N')


def refused(args, *words):
    r = subprocess.run([needlesim, *args], capture_output=True, text=True, timeout=30)
    assert r.returncode == 2 and all(w in r.stderr for w in words), (args, r.returncode, r.stdout, r.stderr)
    print(f'refused ({" ".join(args[1:3])} ...): {r.stderr.strip()[:300]}')


def errors():
    held = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    held.bind(('127.0.0.1', 0))
    held.listen(1)
    refused(['serve', scenario, '--port', str(held.getsockname()[1])], '--port', 'cannot be bound')
    udp = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
    udp.bind(('127.0.0.1', 0))
    refused(['serve', scenario, '--port', '0', '--haptic-port', str(udp.getsockname()[1])], '--haptic-port', 'cannot be bound')
    refused(['serve', scenario, '--host', '300.1.2.3'], '--host', 'not an IPv4 address')
    refused(['serve', scenario, '--port', '70000'], '--port', 'not a port number')
    refused(['serve', os.path.join(work, 'missing.yaml')], 'missing.yaml')
    refused(['serve', os.path.join(source, 'examples', 'explicit', 'target_inclusion_2d.yaml')], 'cannot be stepped')
    # The engine's own line in the scenario, the engines serve steps and the command that runs it.
    mpm = os.path.join(source, 'examples', 'mpm', 'quick_needle_block.yaml')
    with open(mpm) as f:
        line = next(i for i, l in enumerate(f, 1) if l.strip() == 'engine: mpm')
    refused(['serve', mpm], f'{mpm}:{line}:', 'model.engine', "'mpm'", 'lumped, realtime2d or realtime3d',
            'needlesim run')
    refused(['serve', scenario, '--record', source], '--record')
    refused(['replay', os.path.join(source, 'examples')], 'not a recording')


def refused_requests(url):
    """Unknown fields and values of the wrong type: 400 naming the field and what is allowed."""
    for body, field in (({'insert': 'fast'}, 'insert'), ({'warp': 9}, 'warp'), ({'insert': 5}, 'insert'),
                        ({'roll': True}, 'roll')):
        code, answer = post_error(url, '/api/drive', body)
        assert code == 400 and answer['field'] == field and 'allowed: ' in answer['error'], (body, code, answer)
    try:
        post(url, '/api/drive', {'insert': 0, 'pad': 'x' * 100000})
        raise AssertionError('a body of 100 kB was taken')
    except urllib.error.HTTPError as e:
        assert e.code == 413, e.code  # bodies over 64 KiB are not read
    code, answer = post_error(url, '/api/reset', {'hard': True})
    assert code == 400 and answer['field'] == 'hard', answer
    try:
        urllib.request.urlopen(url + '/api/frame?since=abc', timeout=10)
        raise AssertionError('since=abc was taken')
    except urllib.error.HTTPError as e:
        assert e.code == 400 and json.load(e)['field'] == 'since', e.code
    print('refused with 400: {"insert": "fast"}, {"warp": 9}, {"insert": 5}, {"roll": true}, reset {"hard": true}, since=abc; 413: a 100 kB body')


def stepped_after_reset(url, seconds):
    """Waits until the session, rebuilt by a reset, has stepped `seconds` (its time starts over)."""
    before = json.load(urllib.request.urlopen(url + '/api/frame', timeout=10))['state']['time']
    end = time.time() + 30
    started_over = False
    while time.time() < end:
        now = json.load(urllib.request.urlopen(url + '/api/frame', timeout=10))['state']['time']
        started_over = started_over or now < before
        if started_over and now >= seconds:
            return
        time.sleep(0.05)
    raise AssertionError('the session did not start over after POST /api/reset')


def record_with_resets():
    """Two resets during a recorded session: every step is kept, the resets are marked, the replay matches."""
    rec = os.path.join(work, 'resets')
    proc, url = start(scenario, '--port', '0', '--record', rec, '--speed', '10')
    refused_requests(url)
    post(url, '/api/drive', {'insert': 1})
    time.sleep(1.0)
    for _ in range(2):
        post(url, '/api/reset', {})
        stepped_after_reset(url, 0.3)
    post(url, '/api/stop', {})
    out = proc.communicate(timeout=30)[0]
    assert proc.returncode == 0, out
    summary = json.load(open(os.path.join(rec, 'summary.json')))
    results = summary['results']
    commands = list(csv.DictReader(open(os.path.join(rec, 'commands.csv'))))
    resets = [k for k, row in enumerate(commands) if float(row['reset [1]']) == 1]
    assert summary['status'] == 'complete' and results['resets']['value'] == len(resets) == 2, (results, resets)
    assert results['steps']['value'] == len(commands) > resets[-1] > resets[0] > 500, (len(commands), resets)
    assert results['peak_force']['value'] > 0.05, results['peak_force']  # from the insertion before the resets
    times = [float(row['time [s]']) for row in commands]
    assert all(b > a for a, b in zip(times, times[1:])), 'time since the recording started'
    r = subprocess.run([needlesim, 'replay', rec, '--out', os.path.join(work, 'resets-replayed')], capture_output=True,
                       text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
    print(f'recorded with 2 resets: {len(commands)} steps, resets at steps {resets}; ' + r.stdout.strip().splitlines()[-1])


def held_connections(port, idle, trickling, stop):
    """Opens `idle` connections that send nothing and `trickling` ones that send a request one byte every 0.5 s."""
    socks = []
    for k in range(idle + trickling):
        s = socket.create_connection(('127.0.0.1', port), timeout=5)
        socks.append(s)
    request = b'GET /api/info HTTP/1.1\r\nHost: 127.0.0.1\r\nX-Slow: ' + b'x' * 1000

    def trickle():
        for i in range(len(request)):
            if stop.wait(0.5):
                return
            for s in socks[idle:]:
                try:
                    s.send(request[i:i + 1])
                except OSError:
                    pass
    thread = threading.Thread(target=trickle, daemon=True)
    thread.start()
    return socks, thread


def answers_while_connections_are_held():
    proc, url = start(scenario, '--port', '0')
    port = int(url.rsplit(':', 1)[1])
    stop = threading.Event()
    socks, thread = held_connections(port, 32, 32, stop)
    try:
        time.sleep(0.2)  # the server has taken them all
        times = []
        for _ in range(15):
            t0 = time.time()
            info = json.load(urllib.request.urlopen(url + '/api/info', timeout=10))
            times.append(time.time() - t0)
            assert info['engine'] == 'realtime2d'
        print(f'/api/info with 64 connections held (32 idle, 32 sending a byte every 0.5 s): '
              f'median {statistics.median(times) * 1e3:.1f} ms, longest {max(times) * 1e3:.1f} ms')
        assert statistics.median(times) < 0.1 and max(times) < 1.0, times
    finally:
        stop.set()
        thread.join()
        for s in socks:
            s.close()
        post(url, '/api/stop', {})
        proc.communicate(timeout=30)
    assert proc.returncode == 0


def second_signal_still_writes_the_recording():
    """SIGTERM twice: the second arrives while the server stops (an idle connection holds it up)."""
    rec = os.path.join(work, 'twice')
    proc, url = start(scenario, '--port', '0', '--record', rec, '--speed', '10')
    post(url, '/api/drive', {'insert': 1})
    time.sleep(0.5)
    idle = socket.create_connection(('127.0.0.1', int(url.rsplit(':', 1)[1])), timeout=5)
    urllib.request.urlopen(url + '/api/info', timeout=10).read()  # accepted after `idle`: that one is held now
    proc.send_signal(signal.SIGTERM)
    time.sleep(0.3)
    proc.send_signal(signal.SIGTERM)
    out = proc.communicate(timeout=30)[0]
    idle.close()
    assert proc.returncode == 0, (proc.returncode, out)
    assert 'the recording is written' in out, out
    summary = json.load(open(os.path.join(rec, 'summary.json')))
    assert summary['status'] == 'complete' and summary['results']['steps']['value'] > 100, summary['results']
    print('second SIGTERM while stopping: ' + [l for l in out.splitlines() if 'recording' in l][-1])


def warns_beyond_this_machine():
    # 192.0.2.1 (TEST-NET-1) is no machine's address: the bind fails after the warning, nothing is served
    r = subprocess.run([needlesim, 'serve', scenario, '--host', '192.0.2.1', '--port', '0'], capture_output=True,
                       text=True, timeout=60)
    assert 'warning' in r.stderr and 'WITHOUT AUTHENTICATION' in r.stderr and r.returncode == 2, (r.returncode, r.stderr)
    print('--host 192.0.2.1: ' + r.stderr.strip().splitlines()[0][:110] + ' ...')
    r = subprocess.run([needlesim, 'serve', scenario, '--host', '127.0.0.1', '--port', '70000'], capture_output=True,
                       text=True, timeout=60)
    assert 'AUTHENTICATION' not in r.stderr, r.stderr


record_and_replay()
record_with_resets()
answers_while_connections_are_held()
second_signal_still_writes_the_recording()
warns_beyond_this_machine()
errors()
