#!/usr/bin/env python3
"""The README's tour ("A five-minute tour"), run top to bottom as printed.

Each line of the tour's ```sh block runs in bash after its first line (B=...), in a fresh folder
that holds a copy of examples/, the checkout's scripts/ and build/release (a link to this build),
so the checkout's results/ is never touched. A line whose comment gives its time, "(~2.5 min)",
is a long one: --quick leaves those out (and the lines that read what they wrote); without
--quick every line runs. Each line must exit 0, but the CalculiX comparison may exit 77 (ccx
not installed: skipped, as its own test does). A line without a time must take under 30 s of
CPU time (its processes' rusage; the README marks every command over 30 s). OMP_WAIT_POLICY is
passive: OpenMP threads that wait sleep rather than spin, so that on a loaded machine the CPU
time stays the work done.

`serve` lines run with --port 0 (any free port, so that the test never meets another server on
8080): the page is fetched, a --record session is driven in 1 s and out, and the server is
stopped through /api/stop (the recording is written then, for the `replay` line after it).
The haptic client's line is paired with a server it can talk to: `serve --haptic-port 5700`
(the port it names) on the built-in default, as its comment says; that server is stopped after.

usage: readme_tour.py SOURCE_DIR BUILD_DIR WORKDIR [--quick] [--from TEXT]
(--from: start at the first line that contains TEXT, to rerun the end of the tour by hand)
"""
import json
import os
import re
import resource
import shutil
import subprocess
import sys
import time
import urllib.request

TIME_MARK = re.compile(r"\((?:~|about )?(?P<value>[0-9.]+) (?P<unit>s|min|h)\)")
UNIT = {"s": 1.0, "min": 60.0, "h": 3600.0}
UNMARKED_CPU_SECONDS = 30.0


def tour_lines(readme):
    """(command, comment) for each line of the tour's sh block, the B= line first."""
    text = open(readme).read()
    section = text.split("## A five-minute tour", 1)[1]
    block = re.search(r"```sh\n(.*?)```", section, re.S).group(1)
    lines = []
    for line in block.splitlines():
        if not line.strip():
            continue
        command, comment = (re.split(r"\s#\s", line, maxsplit=1) + [""])[:2]
        lines.append((command.strip(), comment.strip()))
    return lines


def children_cpu():
    u = resource.getrusage(resource.RUSAGE_CHILDREN)
    return u.ru_utime + u.ru_stime


def marked_seconds(comment):
    m = TIME_MARK.search(comment)
    return float(m.group("value")) * UNIT[m.group("unit")] if m else None


def prepare(source, build, work):
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.join(work, "build"))
    shutil.copytree(os.path.join(source, "examples"), os.path.join(work, "examples"))
    os.symlink(os.path.join(source, "scripts"), os.path.join(work, "scripts"))
    os.symlink(os.path.abspath(build), os.path.join(work, "build", "release"))


def post(url, path, body):
    req = urllib.request.Request(url + path, data=json.dumps(body).encode(), method="POST",
                                 headers={"Content-Type": "application/json"})
    return json.load(urllib.request.urlopen(req, timeout=10))


def start_serve(command, bash_b, work):
    """Starts a serve line (with --port 0 added); its process and page URL."""
    proc = subprocess.Popen(["bash", "-c", "%s; exec %s --port 0" % (bash_b, command)], cwd=work,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    end = time.time() + 60
    while time.time() < end:
        line = proc.stdout.readline()
        if line.startswith("trainer: "):
            return proc, line.split()[1].rstrip("/")
        if not line:
            break
    proc.kill()
    raise AssertionError("no page URL from: " + command)


def stop_serve(proc, url):
    post(url, "/api/stop", {})
    out = proc.communicate(timeout=60)[0]
    assert proc.returncode == 0, out[-3000:]


def run_serve(command, bash_b, work):
    """A serve line: start, fetch the page, drive a recorded session in and out, stop."""
    proc, url = start_serve(command, bash_b, work)
    page = urllib.request.urlopen(url + "/", timeout=10).read().decode()
    assert "<html" in page.lower(), page[:300]
    if "--record" in command:
        post(url, "/api/drive", {"insert": 1})
        time.sleep(1.0)
        post(url, "/api/drive", {"insert": -1})
        time.sleep(0.5)
    stop_serve(proc, url)


def run_haptic_client(shell_line, bash_b, work):
    """The haptic client's line against `serve --haptic-port 5700` of the built-in default."""
    proc, url = start_serve("$B serve --haptic-port 5700", bash_b, work)
    try:
        p = subprocess.run(["bash", "-c", shell_line], cwd=work, capture_output=True, text=True, timeout=120)
        assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    finally:
        stop_serve(proc, url)


def main():
    source, build, work = sys.argv[1:4]
    os.environ["OMP_WAIT_POLICY"] = "passive"
    quick = "--quick" in sys.argv[4:]
    prepare(source, build, work)
    lines = tour_lines(os.path.join(source, "README.md"))
    assert lines[0][0].startswith("B="), lines[0]
    bash_b = lines[0][0]
    skipped_outputs = []
    if "--from" in sys.argv:
        start = sys.argv[sys.argv.index("--from") + 1]
        lines = lines[:1] + lines[next(i for i, (c, _) in enumerate(lines) if i and start in c):]
    total = time.monotonic()
    for command, comment in lines[1:]:
        seconds = marked_seconds(comment)
        reads_skipped = any(out in command for out in skipped_outputs)
        if quick and (seconds is not None or reads_skipped):
            out = re.search(r"--(?:out|record) (\S+)", command)
            if out:
                skipped_outputs.append(out.group(1))
            print("skipped (--quick, %s): %s" % ("marked %s" % comment if seconds else "reads a skipped output",
                                                 command), flush=True)
            continue
        shell_line = bash_b + "; " + command
        t0 = time.monotonic()
        cpu0 = children_cpu()
        if re.search(r"\$B serve\b", command):
            run_serve(command, bash_b, work)
        elif "haptic_client.py" in command:
            run_haptic_client(command, bash_b, work)
        else:
            p = subprocess.run(["bash", "-c", shell_line], cwd=work, capture_output=True, text=True)
            allowed = (0, 77) if "calculix_compare.py" in command else (0,)
            assert p.returncode in allowed, "%s: exit %d\n%s%s" % (command, p.returncode, p.stdout[-3000:],
                                                                   p.stderr[-3000:])
        took, cpu = time.monotonic() - t0, children_cpu() - cpu0
        print("%6.1f s wall %6.1f s CPU  %s" % (took, cpu, command), flush=True)
        if seconds is None:
            assert cpu < UNMARKED_CPU_SECONDS, "%s: %.0f s of CPU time and no time in its comment" % (command, cpu)
    print("tour: %.1f s" % (time.monotonic() - total))
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
