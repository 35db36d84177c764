#!/usr/bin/env python3
"""The physics rate of `needlesim serve` during an insertion (docs/performance.md).

Starts `needlesim serve SCENARIO --port 0`, holds "insert" for SECONDS through the page's API,
reads the achieved step rate, the wall time of the physics thread's work per step and of the
viewer thread's field computation from GET /api/frame once a second, stops the server and
prints its summary line.

usage: live_rate.py NEEDLESIM SCENARIO [SECONDS]
"""
import json
import subprocess
import sys
import time
import urllib.request

needlesim, scenario = sys.argv[1:3]
seconds = float(sys.argv[3]) if len(sys.argv) > 3 else 5.0
proc = subprocess.Popen([needlesim, 'serve', scenario, '--port', '0'], stdout=subprocess.PIPE, text=True)
url = None
while url is None:
    line = proc.stdout.readline()
    if not line:
        sys.exit('needlesim serve did not start')
    if line.startswith('trainer: '):
        url = line.split()[1].rstrip('/')


def post(path, body):
    urllib.request.urlopen(urllib.request.Request(url + path, data=json.dumps(body).encode(), method='POST',
                                 headers={'Content-Type': 'application/json'}), timeout=10)


post('/api/drive', {'insert': 1})
rates, costs, worst, fields = [], [], 0.0, []
for _ in range(int(seconds)):
    time.sleep(1.0)
    f = json.load(urllib.request.urlopen(url + '/api/frame?since=1000000000', timeout=10))
    rates.append(f['rate'])
    costs.append(f['stepCost'])
    worst = max(worst, f['stepMaxCost'])
    if 'cost' in f['field']:
        fields.append(f['field']['cost'])
depth = f['state']['depth']
post('/api/stop', {})
summary = proc.communicate(timeout=30)[0].strip().splitlines()[-1]
print(f'{scenario}: rate {min(rates):.0f}-{max(rates):.0f} Hz, step {1e6 * min(costs):.0f}-{1e6 * max(costs):.0f} us '
      f'(longest {1e6 * worst:.0f} us), depth {1e3 * depth:.1f} mm')
if fields:
    print(f'surface field in the viewer thread: {1e3 * min(fields):.2f}-{1e3 * max(fields):.2f} ms')
print(summary)
