#!/usr/bin/env python3
"""A study's report.html in headless Chromium (CTest label `browser`): the case table of a
40-case study is wider than a 900 px window, so the page's script says so above it (the
table scrolls sideways inside a box at most 80 % of the window high, its scroll bar on
screen). Screenshot: <workdir>/study_table.png. Exit 77 (CTest: skipped) without Chromium.

usage: report_table_browser_test.py NEEDLESIM SOURCE_DIR WORKDIR
"""
import os
import shutil
import subprocess
import sys

SKIP = 77


def main():
    needlesim, source, workdir = sys.argv[1:4]
    chromium = next((shutil.which(n) for n in ('chromium', 'chromium-browser', 'google-chrome') if shutil.which(n)), None)
    if not chromium:
        print('SKIP: no chromium')
        return SKIP
    os.makedirs(workdir, exist_ok=True)
    study = os.path.join(workdir, 'lhs')
    subprocess.run([needlesim, 'sweep', os.path.join(source, 'examples/studies/lumped_uncertainty_lhs.yaml'),
                    '--out', study, '--overwrite'], check=True, stdout=subprocess.DEVNULL, timeout=120)
    page = 'file://' + os.path.join(study, 'report.html')
    common = [chromium, '--headless', '--no-sandbox', '--disable-gpu', '--window-size=900,700']
    dom = subprocess.run(common + ['--dump-dom', page], capture_output=True, text=True, timeout=60).stdout
    subprocess.run(common + ['--screenshot=' + os.path.join(workdir, 'study_table.png'), page],
                   capture_output=True, timeout=60)
    if '<thead>' not in dom or 'class="tablewrap"' not in dom:
        print('FAIL: no case table in the page')
        return 1
    if 'class="scrollhint"' not in dom:
        print('FAIL: the case table is wider than the window but the page does not say so')
        return 1
    print('ok: the wide case table scrolls in its box and the page says so')
    return 0


if __name__ == '__main__':
    sys.exit(main())
