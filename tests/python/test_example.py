"""examples/python/insertion_forces.py runs headless and writes its two plots."""
import os
import re
import subprocess
import sys

import pytest

from conftest import SOURCE_DIR, eq_5_1


def test_example_script_writes_its_plots(tmp_path):
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("DISPLAY", None)
    p = subprocess.run([sys.executable, str(SOURCE_DIR / "examples" / "python" / "insertion_forces.py"),
                        str(tmp_path / "plots")], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    exit_force = float(re.search(r"exit force: ([0-9.e+-]+) N", p.stdout).group(1))
    assert exit_force == pytest.approx(eq_5_1(0.055, 0.003), rel=2e-3)
    assert "depth=40 mm" in p.stdout and "phase=cutting" in p.stdout
    for name in ("force_depth.png", "tissue_displacement.png"):
        png = tmp_path / "plots" / name
        assert png.is_file() and png.stat().st_size > 10000, name
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
