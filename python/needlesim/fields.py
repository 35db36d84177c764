"""A field time series of a results folder (<name>.xdmf + <name>.h5, io/field_series)
as NumPy arrays. The XDMF file is the index: each step's time, geometry, topology
and attributes name their HDF5 datasets, which are read with h5py (Debian
python3-h5py) as stored, with any number of components (a scalar is 1-D, a
vector or tensor rows x components). A file that cannot be read raises
needlesim.InputError naming it (needlesim.NotFoundError where it does not exist)."""
import os
import pathlib
import re
import xml.etree.ElementTree as ET

import numpy as np

from needlesim._errors import ArgumentTypeError, UnknownNameError, input_error, printable, reading

_XDMF_ALLOWED = "an XDMF file as needlesim writes it, naming HDF5 datasets beside it (docs/results.md)"
_H5_ALLOWED = "the HDF5 file of a needlesim field series, beside its XDMF file (docs/results.md)"


def inside_folder(name):
    """Whether `name` names a file inside the folder it is read from (relative, no '..')."""
    p = pathlib.PurePosixPath(name)
    return bool(name) and "\\" not in name and not p.is_absolute() and ".." not in p.parts


def _h5py():
    try:
        import h5py
    except ImportError as e:  # pragma: no cover - depends on the machine
        raise ImportError("needlesim reads field files with h5py: install Debian's python3-h5py "
                          "(scripts/bootstrap.sh)") from e
    return h5py


class _Ref:
    """An HDF5 dataset named by an XDMF DataItem ("file.h5:/path")."""

    def __init__(self, xdmf, item):
        if item is None:
            raise input_error(xdmf, "an Attribute, Geometry or Topology without a DataItem", _XDMF_ALLOWED)
        if item.get("Format", "XML") != "HDF":
            raise input_error(xdmf, "a DataItem in format '%s'" % printable(item.get("Format", "XML")),
                              "HDF data items (needlesim reads those)")
        text = (item.text or "").strip()
        file, sep, dataset = text.partition(":/")
        if not sep:
            raise input_error(xdmf, "DataItem '%s' does not name 'file.h5:/dataset'" % printable(text), _XDMF_ALLOWED)
        if not inside_folder(file):
            raise input_error(xdmf, "DataItem '%s' names a file outside the XDMF file's folder" % printable(text),
                              "HDF5 files beside the XDMF file")
        self.file = pathlib.Path(xdmf).parent / file
        self.dataset = "/" + dataset


class _Store:
    """The series' HDF5 datasets, read on first use and kept."""

    def __init__(self):
        self._cache = {}

    def array(self, ref):
        key = (str(ref.file), ref.dataset)
        if key not in self._cache:
            self._cache[key] = self._read(ref, lambda d: np.asarray(d[()]))
        return self._cache[key]

    def attributes(self, ref):
        key = ("attrs", str(ref.file), ref.dataset)
        if key not in self._cache:
            self._cache[key] = self._read(ref, lambda d: {k: _text(v) for k, v in d.attrs.items()})
        return self._cache[key]

    @staticmethod
    def _read(ref, what):
        h5py = _h5py()
        with reading(ref.file, _H5_ALLOWED):
            with h5py.File(ref.file, "r") as f:
                if ref.dataset not in f or not isinstance(f[ref.dataset], h5py.Dataset):
                    raise input_error(ref.file, "has no dataset %s" % printable(ref.dataset), _H5_ALLOWED)
                return what(f[ref.dataset])


def _text(v):
    if isinstance(v, bytes):
        return v.decode("utf-8", "replace")
    if isinstance(v, np.ndarray) and v.dtype.kind in "SO" and v.size == 1:
        return _text(v.reshape(-1)[0])
    return v


class _Arrays:
    """Named arrays of one step (point or cell data), read when used."""

    def __init__(self, store, refs):
        self._store = store
        self._refs = refs

    def __getitem__(self, name):
        if name not in self._refs:
            raise UnknownNameError("no array '%s' in this step; it has: %s"
                                   % (printable(name), ", ".join(self._refs) or "none"))
        return self._store.array(self._refs[name])

    def __contains__(self, name):
        return name in self._refs

    def __iter__(self):
        return iter(self._refs)

    def __len__(self):
        return len(self._refs)

    def keys(self):
        return list(self._refs)

    def items(self):
        return [(k, self[k]) for k in self._refs]

    def __repr__(self):
        return "{%s}" % ", ".join("'%s': array%s" % (k, self[k].shape) for k in self._refs)


def _array_name(xdmf_name):
    """The array's name without the unit the XDMF name carries: "displacement [m]" -> "displacement"."""
    return re.sub(r" \[[^\]]*\]$", "", xdmf_name)


class FieldStep:
    """One time step: `time` [s], `points` (n x dim), `cells` (connectivity, or None
    for points without cells), `point_data[name]` and `cell_data[name]` (arrays)."""

    def __init__(self, store, time, cell_type, geometry, topology, point_refs, cell_refs, nodes_per_cell=1):
        self._store = store
        self._nodes_per_cell = nodes_per_cell
        self.time = time
        self.cell_type = cell_type
        self._geometry = geometry
        self._topology = topology
        self.point_data = _Arrays(store, point_refs)
        self.cell_data = _Arrays(store, cell_refs)

    @property
    def points(self):
        return self._store.array(self._geometry)

    @property
    def cells(self):
        """Connectivity, one row per cell (a Polyvertex has one point per row)."""
        if self._topology is None:
            return None
        cells = self._store.array(self._topology)
        if cells.ndim != 1:
            return cells
        with reading(self._topology.file, _H5_ALLOWED):
            return cells.reshape(-1, self._nodes_per_cell)

    def _load(self):
        _ = self.points, self.cells
        for arrays in (self.point_data, self.cell_data):
            for name in arrays:
                _ = arrays[name]

    def __repr__(self):
        return "<FieldStep t=%.6g s: %d points; point data %s; cell data %s>" % (
            self.time, len(self.points), list(self.point_data), list(self.cell_data))


class FieldSeries:
    """A field time series read from its XDMF file (and the HDF5 file it names).

    times        1-D array of the steps' times [s]
    steps        list of FieldStep; series[k] is steps[k]
    points       the first step's points (n x dim); cells its connectivity
    cell_type    XDMF topology: "Quadrilateral", "Triangle", "Tetrahedron", "Hexahedron", "Polyline", "Polyvertex"
    point_data(name) / cell_data(name): the named array of every step stacked (steps x ...)
    units        {array name: unit} where the HDF5 datasets carry a "unit" (or "units") attribute
    """

    def __init__(self, xdmf):
        if not isinstance(xdmf, (str, os.PathLike)):
            raise ArgumentTypeError("needlesim.FieldSeries: xdmf must be a str or a pathlib.Path, not %s"
                                    % type(xdmf).__name__)
        self.path = pathlib.Path(xdmf)
        self.name = self.path.stem
        self._store = _Store()
        self.steps = self._read_index()

    def _read_index(self):
        with reading(self.path, _XDMF_ALLOWED):
            try:
                root = ET.fromstring(self.path.read_bytes())
            except ET.ParseError as e:
                raise input_error(self.path, "is not a readable XDMF file (%s)" % printable(e), _XDMF_ALLOWED) from None
            grids = root.findall("./Domain/Grid")
            steps = []
            for grid in grids:
                members = grid.findall("./Grid") if grid.get("GridType") == "Collection" else [grid]
                steps.extend(self._step(g, k) for k, g in enumerate(members))
            return steps

    def _step(self, grid, k):
        time = grid.find("./Time")
        t = float(time.get("Value")) if time is not None and time.get("Value") is not None else float(k)
        topology = grid.find("./Topology")
        cell_type = topology.get("TopologyType", topology.get("Type", "")) if topology is not None else "Polyvertex"
        topo_item = topology.find("./DataItem") if topology is not None else None
        geometry = grid.find("./Geometry/DataItem")
        if geometry is None:
            raise input_error(self.path, "step %d has no geometry" % k, _XDMF_ALLOWED)
        point_refs, cell_refs = {}, {}
        for attr in grid.findall("./Attribute"):
            refs = cell_refs if attr.get("Center", "Node") == "Cell" else point_refs
            refs[_array_name(attr.get("Name", ""))] = _Ref(self.path, attr.find("./DataItem"))
        nodes_per_cell = int(topology.get("NodesPerElement", "1")) if topology is not None else 1
        if nodes_per_cell < 1:
            raise input_error(self.path, "step %d: NodesPerElement %d" % (k, nodes_per_cell), _XDMF_ALLOWED)
        return FieldStep(self._store, t, cell_type, _Ref(self.path, geometry),
                         None if topo_item is None else _Ref(self.path, topo_item), point_refs, cell_refs,
                         nodes_per_cell)

    @property
    def times(self):
        return np.array([s.time for s in self.steps])

    @property
    def points(self):
        return self.steps[0].points if self.steps else np.empty((0, 0))

    @property
    def cells(self):
        return self.steps[0].cells if self.steps else None

    @property
    def cell_type(self):
        return self.steps[0].cell_type if self.steps else ""

    @property
    def dim(self):
        return self.points.shape[1] if self.points.ndim == 2 else 1

    def point_data_names(self):
        return sorted({n for s in self.steps for n in s.point_data})

    def cell_data_names(self):
        return sorted({n for s in self.steps for n in s.cell_data})

    def point_data(self, name):
        return self._stacked(name, "point_data")

    def cell_data(self, name):
        return self._stacked(name, "cell_data")

    def _stacked(self, name, kind):
        arrays = [getattr(s, kind)[name] for s in self.steps if name in getattr(s, kind)]
        if not arrays:
            raise UnknownNameError("field series '%s' has no %s '%s'; it has: %s" % (
                self.name, kind.replace("_", " "), printable(name),
                ", ".join(getattr(self, kind + "_names")()) or "none"))
        if len(arrays) != len(self.steps) or len({a.shape for a in arrays}) != 1:
            raise input_error(self.path, "'%s' changes shape or is missing in some steps" % printable(name),
                              "steps[k].%s['%s'] for each step" % (kind, printable(name)))
        return np.stack(arrays)

    @property
    def units(self):
        units = {}
        for step in self.steps[:1]:
            for refs in (step.point_data._refs, step.cell_data._refs):
                for name, ref in refs.items():
                    attrs = self._store.attributes(ref)
                    unit = attrs.get("unit", attrs.get("units"))
                    if unit is not None:
                        units[name] = unit
        return units

    def load(self):
        """Read every array into memory."""
        for s in self.steps:
            s._load()
        _ = self.units  # the HDF5 attributes too
        return self

    def __len__(self):
        return len(self.steps)

    def __getitem__(self, k):
        return self.steps[k]

    def __iter__(self):
        return iter(self.steps)

    def __repr__(self):
        if not self.steps:
            return "<FieldSeries '%s': no steps>" % self.name
        return "<FieldSeries '%s': %d steps, t = %.6g..%.6g s, %d points (%s); point data %s; cell data %s>" % (
            self.name, len(self.steps), self.steps[0].time, self.steps[-1].time, len(self.points), self.cell_type,
            self.point_data_names(), self.cell_data_names())
