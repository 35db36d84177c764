#!/usr/bin/env python3
"""`needlesim serve` and `needlesim replay` on the command line (docs/serve.md).

A recorded session driven through the page's API (POST /api/drive, /api/stop) is written as a
complete results folder, `needlesim replay` reproduces its forces.csv; a port in use, a bad host,
a scenario that cannot be stepped live, a --record target that is no results folder and a
replay of a folder that is no recording each end with a message and exit code 2, never a hang.

usage: serve_cli_test.py NEEDLESIM SOURCE_DIR WORKDIR
"""
import csv
import json
import os
import shutil
import socket
import subprocess
import sys
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
    print(f'refused ({" ".join(args[1:3])} ...): {r.stderr.strip()[:150]}')


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
    refused(['serve', scenario, '--record', source], '--record')
    refused(['replay', os.path.join(source, 'examples')], 'not a recording')


record_and_replay()
errors()
