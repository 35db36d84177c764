#!/usr/bin/env python3
"""`needlesim serve` in a real browser (CTest label `browser`, docs/serve.md).

Starts the trainer on a free port and headless Chromium (Debian `chromium`) with its
DevTools protocol (python3-websocket), presses W (a real key event) to insert, holds the
page's Retract button (real mouse events), and checks from the page's own chart data and
DOM that the force plot rises, that the puncture is shown and that retraction reverses the
friction. Screenshots: <workdir>/trainer_inserted.png, trainer_retracted.png.
Every run also checks the first view (the whole tissue in the picture, from the outline the API
gives) and the tilt and roll readout; a scenario with a target inclusion also the anatomy: the
target drawn in its colour (pixels of a screenshot, Pillow) and the live miss distance, in mm,
the distance from the tip to the target's centre before the insertion and nearer after it.
An imported solid (an organ) must also be seen: its surface stands out from the background in
the middle of its picture, not only the few creases of a smooth surface.
Exit 77 (CTest: skipped) with a message where Chromium or python3-websocket is absent.

usage: trainer_browser_test.py NEEDLESIM SCENARIO WORKDIR
"""
import base64
import json
import os
import shutil
import subprocess
import sys
import time
import urllib.request

SKIP = 77


def skip(why):
    print(f'SKIP: {why}')
    sys.exit(SKIP)


def find_chromium():
    for name in ('chromium', 'chromium-browser', 'google-chrome'):
        path = shutil.which(name)
        if path:
            return path
    return None


class DevTools:
    """A minimal Chrome DevTools protocol client over one page's websocket."""

    def __init__(self, ws_url):
        import websocket
        self.ws = websocket.create_connection(ws_url, timeout=30, suppress_origin=True)
        self.next_id = 0

    def call(self, method, **params):
        self.next_id += 1
        self.ws.send(json.dumps({'id': self.next_id, 'method': method, 'params': params}))
        while True:
            msg = json.loads(self.ws.recv())
            if msg.get('id') == self.next_id:
                if 'error' in msg:
                    raise RuntimeError(f'{method}: {msg["error"]}')
                return msg.get('result', {})

    def eval(self, expression):
        r = self.call('Runtime.evaluate', expression=expression, returnByValue=True, awaitPromise=True)
        if 'exceptionDetails' in r:
            raise RuntimeError(f'{expression}: {r["exceptionDetails"]}')
        return r['result'].get('value')

    def wait_for(self, expression, timeout, what):
        end = time.time() + timeout
        while time.time() < end:
            if self.eval(expression):
                return
            time.sleep(0.05)
        raise AssertionError(f'timed out after {timeout} s waiting for {what} ({expression}); '
                             f'page state: {self.eval("JSON.stringify(window.trainer && window.trainer.frame && window.trainer.frame.state)")}, '
                             f'errors: {self.eval("JSON.stringify(window.trainer && window.trainer.errors)")}')

    def key(self, kind, key, code, vk):
        self.call('Input.dispatchKeyEvent', type=kind, key=key, code=code, windowsVirtualKeyCode=vk)

    def mouse(self, kind, x, y):
        self.call('Input.dispatchMouseEvent', type=kind, x=x, y=y, button='left', buttons=1 if kind == 'mousePressed' else 0,
                  clickCount=1)

    def screenshot(self, path):
        data = self.call('Page.captureScreenshot', format='png')['data']
        with open(path, 'wb') as f:
            f.write(base64.b64decode(data))
        print(f'screenshot: {path}')


def start_server(needlesim, scenario):
    proc = subprocess.Popen([needlesim, 'serve', scenario, '--port', '0', '--speed', '8'], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    end = time.time() + 45  # a realtime3d block sets up in seconds, longer on a loaded machine
    lines = []
    while time.time() < end:
        line = proc.stdout.readline()
        if not line:
            break
        lines.append(line)
        if line.startswith('trainer: '):
            return proc, line.split()[1]
    proc.kill()
    raise AssertionError('needlesim serve printed no URL:\n' + ''.join(lines))


def start_chromium(chromium, workdir):
    profile = os.path.join(workdir, 'profile')
    shutil.rmtree(profile, ignore_errors=True)
    args = [chromium, '--headless=new', '--remote-debugging-port=0', f'--user-data-dir={profile}',
            '--window-size=1400,900', '--use-angle=swiftshader', '--enable-unsafe-swiftshader', '--no-first-run',
            '--no-default-browser-check', '--disable-extensions', '--disable-background-networking',
            '--no-sandbox',  # root in CI containers, or no user namespaces; the page is our own, on 127.0.0.1
            'about:blank']
    proc = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=open(os.path.join(workdir, 'chromium.log'), 'w'))
    port_file = os.path.join(profile, 'DevToolsActivePort')
    end = time.time() + 30
    while time.time() < end and not os.path.exists(port_file):
        if proc.poll() is not None:
            raise AssertionError(f'chromium exited with {proc.returncode}; see {workdir}/chromium.log')
        time.sleep(0.1)
    time.sleep(0.2)
    port = int(open(port_file).read().split()[0])
    pages = json.load(urllib.request.urlopen(f'http://127.0.0.1:{port}/json/list', timeout=10))
    page = next(p for p in pages if p.get('type') == 'page')
    return proc, DevTools(page['webSocketDebuggerUrl'])


TARGET_RGB = (0xff, 0x2b, 0xd6)  # trainer.js TARGET_COLOUR


def check_first_view(dt):
    """The eight corners of the tissue's bounds project inside the view, and fill a good part of it."""
    ndc = dt.eval('(() => { const o = trainer.info.outline, out = [];'
                  ' for (const x of [o.lo[0], o.hi[0]]) for (const y of [o.lo[1], o.hi[1]]) for (const z of [o.lo[2], o.hi[2]])'
                  '   { const p = new THREE.Vector3(x, y, z).multiplyScalar(1000).project(trainer.camera); out.push([p.x, p.y]); }'
                  ' return out; })()')
    xs, ys = [p[0] for p in ndc], [p[1] for p in ndc]
    print(f'first view: the tissue spans x {min(xs):.2f}..{max(xs):.2f}, y {min(ys):.2f}..{max(ys):.2f} (view: -1..1)')
    assert all(-1 <= v <= 1 for v in xs + ys), 'the whole tissue is in the first view'
    assert max(max(xs) - min(xs), max(ys) - min(ys)) > 1.0, 'the tissue fills more than half the view'


def number_in(dt, element, unit):
    text = dt.eval(f'document.getElementById("{element}").textContent')
    value, _, rest = text.partition(' ')
    assert rest == unit, f'#{element} reads {text!r}: a number and {unit}'
    return float(value)


def check_angles(dt):
    text = dt.eval('document.getElementById("tilt-roll").textContent')
    tilt, roll = (float(a.strip().rstrip('°')) for a in text.split('·'))
    assert abs(tilt) < 90 and abs(roll) <= 360, f'tilt and roll read {text!r}'


def target_pixels(path):
    from PIL import Image
    pixels = Image.open(path).convert('RGB').getdata()
    # magenta, however lit or seen through the tissue: red and blue alike, green far below both
    # (the |u| colour map, the background and the needle have none such)
    return sum(1 for r, g, b in pixels if is_target(r, g, b))


BACKGROUND_RGB = (0x14, 0x18, 0x1f)  # trainer.js scene.background


def is_target(r, g, b):
    return r > 90 and b > 80 and abs(r - b) < 0.4 * r and g < 0.45 * min(r, b)


def gland_box(dt):
    """The screen box (pixels) of an imported solid's surface vertices, or None for a block or a plane."""
    return dt.eval('(() => { const o = trainer.info.outline;'
                   ' if (o.kind !== "imported" || o.hi[2] - o.lo[2] < 0.05 * (o.hi[0] - o.lo[0])) return null;'
                   ' const v = trainer.info.surface.vertices, r = trainer.renderer.domElement.getBoundingClientRect();'
                   ' let x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;'
                   ' for (let i = 0; i < v.length; i += 3) {'
                   '   const p = new THREE.Vector3(v[i], v[i + 1], v[i + 2]).multiplyScalar(1000).project(trainer.camera);'
                   '   const x = r.left + (p.x + 1) / 2 * r.width, y = r.top + (1 - p.y) / 2 * r.height;'
                   '   x0 = Math.min(x0, x); x1 = Math.max(x1, x); y0 = Math.min(y0, y); y1 = Math.max(y1, y); }'
                   ' return [x0, y0, x1, y1]; })()')


def check_gland_seen(dt, shot):
    """An imported solid (an organ) is seen, not only its few creases: in the middle of its
    picture (the inner 60 % of its screen box, where the needle outside it does not reach), its
    surface stands out from the background on a good part of the pixels besides the target's."""
    box = gland_box(dt)
    if box is None:
        return
    from PIL import Image
    image = Image.open(shot).convert('RGB')
    x0, y0, x1, y1 = box
    w, h = x1 - x0, y1 - y0
    crop = image.crop((int(x0 + 0.2 * w), int(y0 + 0.2 * h), int(x1 - 0.2 * w), int(y1 - 0.2 * h)))
    counted = seen = 0
    for r, g, b in crop.getdata():
        if is_target(r, g, b):
            continue
        counted += 1
        # a plain dark tint of the background is not seeing the surface: 45 of 765 levels
        seen += abs(r - BACKGROUND_RGB[0]) + abs(g - BACKGROUND_RGB[1]) + abs(b - BACKGROUND_RGB[2]) > 45
    share = seen / max(counted, 1)
    print(f'the imported solid stands out on {100 * share:.1f} % of the middle of its picture ({counted} pixels)')
    assert share > 0.08, 'the imported surface is seen (see-through), not just the background'


def check_target_before(dt, workdir):
    """Before the insertion: the target drawn, the miss = |tip - centre| (the target has not moved)."""
    info = dt.eval('trainer.info')
    target = next(i for i in info['inclusions'] if i['target'])
    dt.wait_for('document.getElementById("miss").textContent.endsWith(" mm")', 5, 'the miss distance shown')
    tip = dt.eval('trainer.frame.state.tip')
    expected = sum((a - b) ** 2 for a, b in zip(tip, target['centre'])) ** 0.5 * 1000
    miss = number_in(dt, 'miss', 'mm')
    label = dt.eval('document.getElementById("miss-label").textContent')
    print(f'target {target["name"]}: miss {miss} mm before the insertion ({expected:.3f} mm from the tip); {label!r}')
    assert abs(miss - expected) <= 0.006, 'the miss distance is the tip-to-target distance (mm, 2 decimals)'
    assert target['name'] in label
    shot = os.path.join(workdir, 'trainer_target.png')
    dt.screenshot(shot)
    pixels = target_pixels(shot)
    print(f'{pixels} pixels of the target colour')
    assert pixels > 400, 'the target shows in its colour inside the see-through tissue'
    check_gland_seen(dt, shot)
    return miss


def check_target_after(dt, before, inserted_mm):
    miss = number_in(dt, 'miss', 'mm')
    print(f'miss {miss} mm after {inserted_mm} mm of insertion')
    assert miss < before - 0.5 * inserted_mm, 'the miss distance shrinks as the needle goes towards the target'


def has_target(dt):
    return dt.eval('trainer.info.inclusions.some((i) => i.target)')


def insert_with_key(dt, depth_mm):
    dt.key('keyDown', 'w', 'KeyW', 87)
    dt.wait_for(f'trainer.frame.state.depth * 1000 >= {depth_mm}', 20, f'the tip at {depth_mm} mm')
    dt.key('keyUp', 'w', 'KeyW', 87)


def retract_with_button(dt, by_mm):
    rect = dt.eval('(() => { const r = document.getElementById("btn-retract").getBoundingClientRect();'
                   ' return [r.x + r.width / 2, r.y + r.height / 2]; })()')
    start = dt.eval('trainer.frame.state.depth * 1000')
    dt.mouse('mouseMoved', *rect)
    dt.mouse('mousePressed', *rect)
    dt.wait_for(f'trainer.frame.state.depth * 1000 <= {start - by_mm}', 20, f'retraction by {by_mm} mm')
    dt.mouse('mouseReleased', *rect)


def check_plot(dt):
    """The page's chart and samples: force rises, puncture shown, friction reverses."""
    s, chart_points = dt.eval('[trainer.samples, trainer.chart.data.datasets[0].data.length]')
    marker = dt.eval('trainer.chart.data.datasets[2].data')
    events = dt.eval('document.getElementById("events").textContent')
    deepest = max(range(len(s)), key=lambda i: s[i][1])
    inserting = [x for x in s[:deepest] if x[6] >= 2]
    # retraction while the tip is still 2 mm deep in the tissue (phase >= 2): on a loaded machine the
    # held button can take the needle out, where there is no friction to reverse (the phase stays 3)
    retracting = [x for x in s[deepest + 1:] if s[deepest][1] - x[1] > 1e-3 and x[6] >= 2 and x[1] > 2e-3]
    if os.environ.get('TRAINER_TEST_DUMP'):
        json.dump(s, open(os.environ['TRAINER_TEST_DUMP'], 'w'))
    print(f'{len(s)} samples, {chart_points} chart points; peak axial {max(x[2] for x in s):.3f} N; events: {events!r}')
    assert chart_points == len(s) and chart_points > 50, 'the force plot holds the samples'
    early, late = [x[2] for x in s if 0 < x[1] < 0.5e-3], [x[2] for x in inserting[-20:]]
    assert late and max(late) > 0.05 and min(late) > (max(early) if early else 0.0), 'the force plot rises with depth'
    assert 'puncture at' in events and len(marker) == 1, 'the puncture is shown on the page and the plot'
    assert inserting and min(x[3] for x in inserting[len(inserting) // 2:]) > 0, 'friction resists insertion (> 0)'
    # the tissue first rides along with the shaft (sticking), then slips: friction < 0
    assert retracting and max(x[3] for x in retracting[-len(retracting) // 4:]) < 0, \
        'retraction reverses the friction (< 0 once the tissue slips)'
    assert min(x[2] for x in retracting) < 0, 'the axial force turns negative on retraction'
    print(f'friction: inserting {inserting[-1][3]:+.3f} N, retracting {retracting[-1][3]:+.3f} N')


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    needlesim, scenario, workdir = sys.argv[1:]
    chromium = find_chromium()
    if not chromium:
        skip('chromium is not installed (Debian package chromium; scripts/bootstrap.sh)')
    try:
        import websocket  # noqa: F401
    except ImportError:
        skip('python3-websocket is not installed (scripts/bootstrap.sh)')
    os.makedirs(workdir, exist_ok=True)
    started = time.time()
    server, url = start_server(needlesim, scenario)
    browser = None
    try:
        browser, dt = start_chromium(chromium, workdir)
        dt.call('Page.enable')
        dt.call('Page.navigate', url=url)
        dt.wait_for('window.trainer && trainer.frames > 5 && trainer.info !== null', 40, 'the page to draw frames')
        triangles = dt.eval('trainer.renderer.info.render.triangles')
        print(f'page up at {url} after {time.time() - started:.1f} s; WebGL draws {triangles} triangles')
        assert triangles >= dt.eval('trainer.info.surface.triangles.length / 3'), 'the tissue surface is drawn'
        check_first_view(dt)
        check_angles(dt)
        miss = check_target_before(dt, workdir) if has_target(dt) else None
        insert_with_key(dt, 14.0)
        dt.wait_for('document.getElementById("events").textContent.includes("puncture")', 5, 'the puncture shown')
        time.sleep(0.3)
        dt.screenshot(os.path.join(workdir, 'trainer_inserted.png'))
        if miss is not None:
            check_target_after(dt, miss, 14.0)
        retract_with_button(dt, 6.0)
        time.sleep(0.3)
        dt.screenshot(os.path.join(workdir, 'trainer_retracted.png'))
        check_plot(dt)
        assert dt.eval('trainer.errors.length') == 0, dt.eval('JSON.stringify(trainer.errors)')
        dt.eval('document.getElementById("btn-stop").click()')
        assert server.wait(timeout=10) == 0, 'needlesim serve stops cleanly on POST /api/stop'
        print(f'passed in {time.time() - started:.1f} s')
    finally:
        if browser:
            browser.terminate()
            try:
                browser.wait(timeout=10)
            except subprocess.TimeoutExpired:
                browser.kill()
        if server.poll() is None:
            server.kill()


if __name__ == '__main__':
    main()
