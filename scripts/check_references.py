#!/usr/bin/env python3
"""Every "seed NNN" cited in the docs, the README, the examples and the sources is a
publication listed in docs/references.md (a row starting "| NNN |")."""
import pathlib
import re
import sys

root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
listed = set(re.findall(r"^\| (\d{3}) \|", (root / "docs" / "references.md").read_text(), re.M))
files = [root / "README.md", *root.glob("docs/**/*.md"), *root.glob("examples/**/*.yaml"),
         *root.glob("src/**/*.[ch]pp")]
missing = {}
for f in files:
    for n, line in enumerate(f.read_text(errors="replace").splitlines(), 1):
        for seed in re.findall(r"\bseeds? (\d{3})\b", line):
            if seed not in listed:
                missing.setdefault(seed, []).append(f"{f.relative_to(root)}:{n}")
for seed, where in sorted(missing.items()):
    print(f"seed {seed} is cited but not in docs/references.md: {', '.join(where[:5])}")
print(f"{len(files)} files read; seeds listed: {', '.join(sorted(listed))}")
sys.exit(1 if missing or not listed else 0)
