"""needlesim: needle insertion into soft tissue (forces, deflection, steering, deformation).

    import needlesim
    s = needlesim.load("examples/gelatin_18G_3mms.yaml")
    r = needlesim.run(s)                        # in memory
    r.tables["forces"]["force_total"]           # numpy array
    r.units["forces"]["force_total"]            # 'N'
    r.results["exit_force"]                     # Quantity(value=0.2989..., unit='N')
    r = needlesim.run(s2, fields=True)          # with the engine's fields as arrays
    session = needlesim.Session(s)              # realtime2d or lumped, stepped by the caller

docs/python.md describes the package.
"""
import os
import tempfile

from needlesim._core import (
    InputError,
    LumpedForceModel,
    MotionSample,
    Scenario,
    Session,
    SessionStep,
    SolverError,
    __version__,
    default_scenario,
    engines,
    git_revision,
    load,
    schema,
)
from needlesim import _core
from needlesim.fields import FieldSeries, FieldStep
from needlesim.results import Quantity, Results, Table, open_results

__all__ = [
    "FieldSeries",
    "FieldStep",
    "InputError",
    "LumpedForceModel",
    "MotionSample",
    "Quantity",
    "Results",
    "Scenario",
    "Session",
    "SessionStep",
    "SolverError",
    "Table",
    "__version__",
    "default_scenario",
    "engines",
    "git_revision",
    "load",
    "open_results",
    "run",
    "schema",
]


def run(scenario, out=None, *, overwrite=False, fields=False):
    """Run the scenario's engine and return its Results.

    Without `out`: in memory (no files); tables and key results only, unless
    `fields=True`, which runs into a temporary results folder, reads everything
    (tables, key results, the engine's fields as arrays) and removes the folder.
    With `out` (a str or pathlib.Path): writes the results folder there, as
    `needlesim run --out`, and returns it read back (fields are read from its
    .h5 files when used). `overwrite` replaces an earlier needlesim results
    folder at `out`. Bad input raises InputError, a solver that stops SolverError.
    """
    if not isinstance(scenario, Scenario):
        raise TypeError("needlesim.run: expected a needlesim.Scenario (needlesim.load), got %s"
                        % type(scenario).__name__)
    if out is not None and not isinstance(out, (str, os.PathLike)):
        raise TypeError("needlesim.run: out must be a str or a pathlib.Path, got %s" % type(out).__name__)
    if out is not None and os.fspath(out) != "":
        return _run_to_folder(scenario, out, overwrite)
    if fields:
        with tempfile.TemporaryDirectory(prefix="needlesim-") as tmp:
            results = _run_to_folder(scenario, os.path.join(tmp, "run"), False)
            results.load()
            results.folder = None
            return results
    return Results.from_memory(scenario, _core.run_in_memory(scenario))


def _run_to_folder(scenario, out, overwrite):
    """The results folder read back, with the tables exactly as the engine made them."""
    written = _core.run_to_folder(scenario, out, overwrite)
    tables = {name: Table(name, cols, data) for name, (cols, data) in written["tables"].items()}
    return open_results(written["folder"], tables=tables)
