"""needlesim: needle insertion into soft tissue (forces, deflection, steering, deformation).

    import needlesim
    s = needlesim.load("examples/gelatin_18G_3mms.yaml")
    r = needlesim.run(s)                        # in memory
    r.tables["forces"]["force_total"]           # numpy array
    r.units["forces"]["force_total"]            # 'N'
    r.results["exit_force"]                     # Quantity(value=0.2989..., unit='N')
    r = needlesim.run(s2, fields=True)          # with the engine's fields as arrays
    session = needlesim.Session(s)              # realtime2d or lumped, stepped by the caller

Every error the package raises is a needlesim.InputError (bad input: a scenario,
an argument, a results folder) or a needlesim.SolverError (a solver that stops),
with the message the CLI gives; docs/python.md "Errors" lists them.

docs/python.md describes the package.
"""
import functools
import os
import tempfile

# OpenMP's idle threads spin briefly, then sleep: libgomp reads this when the extension loads
# (the CLI does the same, apps/needlesim/openmp_wait.cpp says why). A caller's own choice is kept.
if "OMP_WAIT_POLICY" not in os.environ and "GOMP_SPINCOUNT" not in os.environ:
    os.environ["GOMP_SPINCOUNT"] = "1000"

from needlesim._core import (
    ArgumentTypeError,
    Inclusion,
    InputError,
    LumpedForceModel,
    MotionSample,
    NotFoundError,
    Scenario,
    Session,
    SessionStep,
    SolverError,
    UnknownNameError,
    __version__,
    default_scenario,
    engines,
    git_revision,
    load,
    schema,
)
from needlesim import _core
from needlesim._errors import printable as _printable, require_type as _require_type
from needlesim.fields import FieldSeries, FieldStep
from needlesim.results import Quantity, Results, Table, open_results

__all__ = [
    "ArgumentTypeError",
    "FieldSeries",
    "FieldStep",
    "Inclusion",
    "InputError",
    "LumpedForceModel",
    "MotionSample",
    "NotFoundError",
    "Quantity",
    "Results",
    "Scenario",
    "Session",
    "SessionStep",
    "SolverError",
    "Table",
    "UnknownNameError",
    "__version__",
    "default_scenario",
    "engines",
    "git_revision",
    "load",
    "open_results",
    "plan",
    "run",
    "schema",
]


def _typed_arguments(function, name):
    """`function` (compiled) with a call whose arguments have the wrong types raising
    ArgumentTypeError (an InputError and a TypeError) rather than pybind11's TypeError."""

    @functools.wraps(function)
    def call(*args, **kwargs):
        try:
            return function(*args, **kwargs)
        except TypeError as e:
            if isinstance(e, InputError):
                raise
            raise ArgumentTypeError("needlesim.%s: %s" % (name, _printable(e, 1000))) from None

    return call


def _wrap_compiled():
    global load, default_scenario, schema, engines
    load = _typed_arguments(load, "load")
    default_scenario = _typed_arguments(default_scenario, "default_scenario")
    schema = _typed_arguments(schema, "schema")
    engines = _typed_arguments(engines, "engines")
    for cls, methods in ((Scenario, ("motion_at", "with_values")),
                         (Session, ("__init__", "step", "needle_shape")),
                         (LumpedForceModel, ("__init__", "step", "reset"))):
        for method in methods:
            setattr(cls, method, _typed_arguments(getattr(cls, method), "%s.%s" % (cls.__name__, method)))


_wrap_compiled()


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
    _require_type("needlesim.run", "scenario", scenario, Scenario, "a needlesim.Scenario (needlesim.load)")
    if out is not None:
        _require_type("needlesim.run", "out", out, (str, os.PathLike), "a str or a pathlib.Path")
    _require_type("needlesim.run", "overwrite", overwrite, bool, "True or False")
    _require_type("needlesim.run", "fields", fields, bool, "True or False")
    if out is not None and os.fspath(out) != "":
        return _run_to_folder(scenario, out, overwrite)
    if fields:
        with tempfile.TemporaryDirectory(prefix="needlesim-") as tmp:
            results = _run_to_folder(scenario, os.path.join(tmp, "run"), False)
            results.load()
            results.folder = None
            return results
    return Results.from_memory(scenario, _core.run_in_memory(scenario))


def plan(scenario):
    """Plan a needle path to the scenario's plan target around its obstacles (docs/planning.md)
    and return its Results in memory: key results (feasible, planned_miss, entry_offset,
    entry_angle, bevel_roll, rotations, clearance_<name>, planning_time, paths_per_second,
    error_p50, error_p95, ...) and the tables plan, path and error_distribution. A scenario
    without a plan section, or one that cannot be planned, raises InputError; a target that no
    path reaches gives feasible 0 with the reason in warnings and the closest approach in path.
    """
    _require_type("needlesim.plan", "scenario", scenario, Scenario, "a needlesim.Scenario (needlesim.load)")
    return Results.from_memory(scenario, _core.plan_in_memory(scenario))


def _run_to_folder(scenario, out, overwrite):
    """The results folder read back, with the tables exactly as the engine made them."""
    written = _core.run_to_folder(scenario, out, overwrite)
    tables = {name: Table(name, cols, data) for name, (cols, data) in written["tables"].items()}
    return open_results(os.fsdecode(written["folder"]), tables=tables)
