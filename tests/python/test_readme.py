"""The README's Python snippet (section "Use it from Python"), run exactly as printed from the
repository's folder, and its comments' claims checked on what it leaves behind."""
import os
import re

import pytest

from conftest import SOURCE_DIR


def readme_python_snippet():
    """The ```python block of the README's section 'Use it from Python', as printed."""
    text = (SOURCE_DIR / "README.md").read_text()
    section = text.split("## Use it from Python", 1)[1].split("\n## ", 1)[0]
    return re.search(r"```python\n(.*?)```", section, re.S).group(1)


def test_readme_python_snippet_runs_as_printed(monkeypatch):
    monkeypatch.chdir(SOURCE_DIR)  # its paths are the repository's, as the README says
    names = {}
    exec(compile(readme_python_snippet(), "README.md (Use it from Python)", "exec"), names)
    r, session = names["r"], names["session"]
    assert r.units["forces"]["force_total"] == "N"
    assert r.results["exit_force"].unit == "N"
    printed = re.search(r"Quantity\(value=([0-9.]+)\.\.\., unit='N'\)", readme_python_snippet()).group(1)
    assert str(r.results["exit_force"].value).startswith(printed)
    assert names["step"].force_total > 0.0
    assert session.displacement.shape[1] == 2
