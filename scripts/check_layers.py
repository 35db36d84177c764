#!/usr/bin/env python3
"""Checks needlesim's layering: every #include "needlesim/<layer>/..." in a file of
src/needlesim/<layer>/ names its own layer or one the table (src/needlesim/layers.txt) lets it
use, directly or through the layers below; the table itself is one-way (a layer names only
layers above it in the file) and names every folder. Exit 1 with one line per violation."""
import argparse
import re
import sys
from pathlib import Path

INCLUDE = re.compile(r'^\s*#\s*include\s+"needlesim/([^"]+)"')
# Each engine's settings (model.<engine>) are declared beside the engine but read by the scenario.
SECTION = re.compile(r"^engines/[^/]+/[^/]*_section\.(hpp|cpp)$")


def read_table(path):
    """{layer: set of layers it names}, in file order; exits on a wrong-way or unknown entry."""
    table = {}
    for number, line in enumerate(path.read_text().splitlines(), 1):
        if not line.strip() or line.startswith("#"):
            continue
        layer, _, below = line.partition(":")
        for name in below.split():
            if name not in table:
                sys.exit(f"{path}:{number}: {layer} names {name}, which is not a layer above it in the table")
        table[layer.strip()] = set(below.split())
    return table


def allowed_layers(table):
    """Each layer with every layer it may use (what it names, and what those may use)."""
    closure = {}
    for layer, below in table.items():  # file order: the layers below are done already
        closure[layer] = {layer}.union(*(closure[name] for name in below))
    return closure


def layer_of(relative):
    """The layer of a path relative to src/needlesim (needlesim.hpp: the public API)."""
    if SECTION.match(relative):
        return "scenario"
    return relative.split("/")[0] if "/" in relative else "api"


def violations(root, table):
    allowed = allowed_layers(table)
    for folder in sorted(p.name for p in root.iterdir() if p.is_dir()):
        if folder not in table:
            yield f"{root / folder}: folder not in the layer table"
    for path in sorted(root.rglob("*")):
        if path.suffix not in (".hpp", ".cpp", ".h") or not path.is_file():
            continue
        layer = layer_of(path.relative_to(root).as_posix())
        if layer not in allowed:
            continue
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            match = INCLUDE.match(line)
            if match and layer_of(match.group(1)) not in allowed[layer]:
                yield (f"{path}:{number}: layer {layer} includes needlesim/{match.group(1)} "
                       f"(layer {layer_of(match.group(1))}); it may use only "
                       f"{', '.join(sorted(allowed[layer]))}")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--table", type=Path, required=True, help="layers.txt")
    parser.add_argument("root", type=Path, help="src/needlesim")
    args = parser.parse_args()
    found = list(violations(args.root, read_table(args.table)))
    for line in found:
        print(line)
    print(f"{len(found)} wrong-way include(s)" if found else "layers hold")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
