"""Results of a run as NumPy arrays: key results with units, tables by column,
fields by name (needlesim.fields). Made from an in-memory run or read from a
results folder (summary.json, <table>.csv, <field>.xdmf + .h5; docs/results.md).
A folder that cannot be read raises needlesim.InputError naming the file."""
import json
import math
import os
import pathlib
import re
from typing import NamedTuple

import numpy as np

from needlesim._errors import (ArgumentTypeError, InputError, NotFoundError, UnknownNameError, input_error,
                               printable, reading)
from needlesim.fields import FieldSeries, inside_folder


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
        if column not in self.units:
            raise UnknownNameError("table '%s' has no column '%s'; its columns: %s"
                                   % (self.name, printable(column), ", ".join(self.columns)))
        return self.data[:, self.columns.index(column)]

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


_CSV_ALLOWED = 'a results table: a header "name [unit]", ... and rows of numbers, one per column (docs/results.md)'


def read_csv_table(path):
    """A results folder's <name>.csv (header "name [unit]") as a Table."""
    path = pathlib.Path(path)
    with reading(path, _CSV_ALLOWED):
        lines = path.read_bytes().decode("utf-8").splitlines()
        columns = []
        for h in lines[0].split(",") if lines else []:
            m = _HEADER.match(h)
            columns.append((m.group(1), m.group(2)) if m else (h, ""))
        rows = [line for line in lines[1:] if line]
        return Table(path.stem, columns, _csv_rows(path, rows, len(columns)))


def _csv_rows(path, rows, count):
    """The rows as a rows x count array; a row that is not `count` numbers is named by its line."""
    if not rows:
        return np.empty((0, count))
    try:
        data = np.loadtxt(rows, delimiter=",", ndmin=2)
        if data.shape[1] == count:
            return data
    except ValueError:
        pass
    for k, row in enumerate(rows):
        cells = row.split(",")
        if len(cells) != count:
            raise input_error("%s:%d" % (path, k + 2), "has %d values (got '%s')" % (len(cells), printable(row, 60)),
                              "%d numbers, one per column of the header" % count)
        for cell in cells:
            try:
                float(cell)
            except ValueError:
                raise input_error("%s:%d" % (path, k + 2), "'%s' is not a number" % printable(cell, 60),
                                  "%d numbers, one per column of the header" % count) from None
    raise input_error(path, "cannot be read as a table", _CSV_ALLOWED)


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
        raise UnknownNameError("Results has no '%s'; allowed: results, tables, notes, warnings, fields, folder"
                               % printable(key))

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


_FOLDER_ALLOWED = "a needlesim results folder (needlesim run --out, needlesim.run(out=...); docs/results.md)"
_SUMMARY_ALLOWED = "a results folder's summary.json as needlesim writes it (docs/results.md)"


def open_results(folder, tables=None):
    """A results folder (written by `needlesim run`, `needlesim sweep` or needlesim.run(out=...))
    as Results: key results from summary.json, tables from its CSV files (or
    `tables`, {name: Table}, when given), fields from its XDMF + HDF5 files (read when used).
    A folder that is missing raises needlesim.NotFoundError, one that cannot be read
    (a file missing, truncated or not as needlesim writes it) needlesim.InputError."""
    if not isinstance(folder, (str, os.PathLike)):
        raise ArgumentTypeError("needlesim.open_results: folder must be a str or a pathlib.Path, not %s"
                                % type(folder).__name__)
    if tables is not None and not isinstance(tables, dict):
        raise ArgumentTypeError("needlesim.open_results: tables must be a dict {name: Table} or None, not %s"
                                % type(tables).__name__)
    folder = pathlib.Path(folder)
    if not folder.is_dir():
        problem = "is not a folder" if folder.exists() else "does not exist"
        raise input_error(folder, problem, _FOLDER_ALLOWED, NotFoundError)
    summary_path = folder / "summary.json"
    if not summary_path.is_file():
        raise input_error(folder, "is not a needlesim results folder: it has no summary.json", _FOLDER_ALLOWED,
                          NotFoundError)
    summary = _read_summary(summary_path)
    files = summary["files"]
    with reading(summary_path, _SUMMARY_ALLOWED):
        results = {k: Quantity(v.get("value"), v.get("unit", ""), v.get("meaning", ""))
                   for k, v in summary["results"].items()}
    if tables is None:
        tables = {pathlib.Path(f).stem: read_csv_table(folder / f) for f in files if f.endswith(".csv")}
    fields = {pathlib.Path(f).stem: FieldSeries(folder / f) for f in files if f.endswith(".xdmf")}
    scenario = summary["scenario"]
    return Results(summary["engine"], scenario.get("name", folder.name), results, tables, fields,
                   summary["notes"], summary["warnings"], summary["status"], folder)


# summary.json's members that open_results reads: (name, type, default when absent).
_SUMMARY_MEMBERS = (("files", list, []), ("results", dict, {}), ("scenario", dict, {}), ("engine", str, ""),
                    ("notes", list, []), ("warnings", list, []), ("status", str, ""))


def _read_summary(path):
    """summary.json as a dict whose members open_results reads have their types (an InputError naming
    the file, and the line or member, otherwise)."""
    with reading(path, _SUMMARY_ALLOWED):
        text = path.read_bytes().decode("utf-8")
    try:
        summary = json.loads(text)
    except json.JSONDecodeError as e:
        raise input_error("%s:%d:%d" % (path, e.lineno, e.colno), "is not valid JSON (%s)" % e.msg,
                          _SUMMARY_ALLOWED) from None
    except (ValueError, RecursionError) as e:
        raise input_error(path, "is not valid JSON (%s)" % printable(e), _SUMMARY_ALLOWED) from None
    if not isinstance(summary, dict):
        raise input_error(path, "holds a JSON %s, not an object" % type(summary).__name__, _SUMMARY_ALLOWED)
    for name, kind, default in _SUMMARY_MEMBERS:
        summary.setdefault(name, default)
        if not isinstance(summary[name], kind):
            raise input_error(path, "'%s' is a %s, not a %s" % (name, type(summary[name]).__name__, kind.__name__),
                              _SUMMARY_ALLOWED)
    for name in ("notes", "warnings"):
        summary[name] = [str(x) for x in summary[name]]
    for f in summary["files"]:
        if not isinstance(f, str) or not inside_folder(f):
            raise input_error(path, "'files' names '%s', which is not a file of the folder" % printable(f),
                              "names of files inside the results folder")
    for k, v in summary["results"].items():
        if not isinstance(v, dict) or not isinstance(v.get("value", 0.0), (int, float, type(None))) \
                or isinstance(v.get("value"), bool):
            raise input_error(path, "results['%s'] is not {value: a number, unit: ...}" % printable(k),
                              _SUMMARY_ALLOWED)
    return summary
