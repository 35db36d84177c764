"""Results of a run as NumPy arrays: key results with units, tables by column,
fields by name (needlesim.fields). Made from an in-memory run or read from a
results folder (summary.json, <table>.csv, <field>.xdmf + .h5; docs/results.md)."""
import json
import math
import pathlib
import re
from typing import NamedTuple

import numpy as np

from needlesim.fields import FieldSeries


class _Value(NamedTuple):
    value: float
    unit: str


class Quantity(_Value):
    """A key result: the pair (value, unit) in SI, with `.meaning` saying what it is.

    Unpacks as `value, unit = q`; `float(q)` is the value."""

    def __new__(cls, value, unit, meaning=""):
        self = super().__new__(cls, math.nan if value is None else float(value), unit)
        self.meaning = meaning
        return self

    def __float__(self):
        return self.value

    def __str__(self):
        return "%.6g" % self.value if self.unit in ("1", "") else "%.6g %s" % (self.value, self.unit)


class Table:
    """A table of named columns with units: `t["force_total"]` is a 1-D float64
    array, `t.units["force_total"]` its unit, `t.data` the rows x columns array."""

    def __init__(self, name, columns, data):
        self.name = name
        self.columns = [c for c, _ in columns]
        self.units = {c: u for c, u in columns}
        self.data = np.asarray(data, dtype=float).reshape(-1, len(self.columns))

    def __getitem__(self, column):
        try:
            return self.data[:, self.columns.index(column)]
        except ValueError:
            raise KeyError("table '%s' has no column '%s'; its columns: %s"
                           % (self.name, column, ", ".join(self.columns))) from None

    def __contains__(self, column):
        return column in self.units

    def __iter__(self):
        return iter(self.columns)

    def __len__(self):
        return self.data.shape[0]

    def keys(self):
        return list(self.columns)

    def items(self):
        return [(c, self[c]) for c in self.columns]

    def __repr__(self):
        shown = ", ".join("%s [%s]" % (c, self.units[c]) for c in self.columns[:6])
        more = ", ... (%d columns)" % len(self.columns) if len(self.columns) > 6 else ""
        return "<Table '%s': %d rows; %s%s>" % (self.name, len(self), shown, more)


_HEADER = re.compile(r"^(.*) \[(.*)\]$")


def read_csv_table(path):
    """A results folder's <name>.csv (header "name [unit]") as a Table."""
    path = pathlib.Path(path)
    lines = path.read_text(encoding="utf-8").splitlines()
    columns = []
    for h in lines[0].split(",") if lines else []:
        m = _HEADER.match(h)
        columns.append((m.group(1), m.group(2)) if m else (h, ""))
    rows = [line for line in lines[1:] if line]
    data = np.loadtxt(rows, delimiter=",", ndmin=2) if rows else np.empty((0, len(columns)))
    return Table(path.stem, columns, data)


class Results:
    """A run's results.

    results   {key: Quantity(value, unit)}     key results in SI
    tables    {name: Table}                     e.g. tables["forces"]["force_total"]
    units     {table: {column: unit}}
    fields    {name: FieldSeries}              the engine's fields (runs with a folder or fields=True)
    notes, warnings                             what the engine reported
    status    "complete" or "stopped"; folder: the results folder (None in memory)
    """

    def __init__(self, engine, name, results, tables, fields=None, notes=(), warnings=(), status="complete",
                 folder=None):
        self.engine = engine
        self.name = name
        self.results = dict(results)
        self.tables = dict(tables)
        self.fields = dict(fields or {})
        self.notes = list(notes)
        self.warnings = list(warnings)
        self.status = status
        self.folder = folder

    @property
    def units(self):
        return {name: dict(t.units) for name, t in self.tables.items()}

    @classmethod
    def from_memory(cls, scenario, raw):
        """From needlesim._core.run_in_memory's dictionary."""
        results = {k: Quantity(v, u, m) for k, (v, u, m) in raw["results"].items()}
        tables = {name: Table(name, cols, data) for name, (cols, data) in raw["tables"].items()}
        return cls(scenario.engine, scenario.name, results, tables, {}, raw["notes"], raw["warnings"])

    def load(self):
        """Read every field array into memory (the folder may then go away)."""
        for series in self.fields.values():
            series.load()
        return self

    def __getitem__(self, key):
        """r["results"], r["tables"], r["notes"], r["warnings"], r["fields"], r["folder"]: the attributes."""
        if key in ("results", "tables", "notes", "warnings", "fields"):
            return getattr(self, key)
        if key == "folder":
            return None if self.folder is None else str(self.folder)
        raise KeyError(key)

    def __repr__(self):
        lines = ["<needlesim.Results of '%s' (%s), %s" % (self.name, self.engine, self.status)]
        if self.results:
            shown = ["%s = %s" % (k, q) for k, q in list(self.results.items())[:8]]
            more = ", ... (%d)" % len(self.results) if len(self.results) > 8 else ""
            lines.append("  results: " + ", ".join(shown) + more)
        if self.tables:
            lines.append("  tables: " + ", ".join("%s (%d x %d)" % (n, len(t), len(t.columns))
                                                  for n, t in self.tables.items()))
        if self.fields:
            lines.append("  fields: " + ", ".join("%s (%d steps)" % (n, len(f)) for n, f in self.fields.items()))
        if self.warnings:
            lines.append("  warnings: %d" % len(self.warnings))
        if self.folder is not None:
            lines.append("  folder: %s" % self.folder)
        return "\n".join(lines) + ">"


def open_results(folder, tables=None):
    """A results folder (written by `needlesim run`, `needlesim sweep` or needlesim.run(out=...))
    as Results: key results from summary.json, tables from its CSV files (or
    `tables`, {name: Table}, when given), fields from its XDMF + HDF5 files (read when used)."""
    folder = pathlib.Path(folder)
    summary_path = folder / "summary.json"
    if not summary_path.is_file():
        raise FileNotFoundError("%s is not a needlesim results folder: it has no summary.json" % folder)
    with open(summary_path, encoding="utf-8") as f:
        summary = json.load(f)
    files = summary.get("files", [])
    results = {k: Quantity(v.get("value"), v.get("unit", ""), v.get("meaning", ""))
               for k, v in summary.get("results", {}).items()}
    if tables is None:
        tables = {pathlib.Path(f).stem: read_csv_table(folder / f) for f in files if f.endswith(".csv")}
    fields = {pathlib.Path(f).stem: FieldSeries(folder / f) for f in files if f.endswith(".xdmf")}
    scenario = summary.get("scenario", {})
    return Results(summary.get("engine", ""), scenario.get("name", folder.name), results, tables, fields,
                   summary.get("notes", []), summary.get("warnings", []), summary.get("status", ""), folder)
