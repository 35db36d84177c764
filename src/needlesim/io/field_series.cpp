#include "needlesim/io/field_series.hpp"

#include <fmt/format.h>
#include <hdf5.h>

#include <cerrno>
#include <cmath>
#include <unistd.h>

#include "needlesim/core/error.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/binary_state.hpp"

namespace needlesim::io {
namespace {

struct Attr {
  std::string name;
  bool cell;
  int components;  // as stored: a 2D series' vectors have 3
  std::string dataset;
  std::size_t count;
  std::string unit;
  bool integer = false;  // int32 (a label), else float64
};

struct Step {
  double time;
  std::string points;  // dataset of this step's points, empty = reference mesh
  std::size_t npoints;
  std::vector<Attr> attrs;
};

const char* topologyName(CellType t) {
  switch (t) {
    case CellType::Points: return "Polyvertex";
    case CellType::Triangle: return "Triangle";
    case CellType::Quad: return "Quadrilateral";
    case CellType::Tetra: return "Tetrahedron";
    case CellType::Hexa: return "Hexahedron";
    case CellType::Line: return "Polyline";
  }
  return "Polyvertex";
}

// An HDF5 identifier closed once, on every path out of the scope that made it.
struct H5Handle {
  hid_t id;
  herr_t (*closer)(hid_t);
  H5Handle(hid_t h, herr_t (*c)(hid_t)) : id(h), closer(c) {}
  H5Handle(const H5Handle&) = delete;
  H5Handle& operator=(const H5Handle&) = delete;
  herr_t close() {
    const hid_t h = id;
    id = -1;
    return h >= 0 ? closer(h) : 0;
  }
  ~H5Handle() { close(); }
};

// HDF5 prints its error stack on stderr by default (thousands of lines when a
// disk fills); needlesim checks every call and reports one Error instead.
void silenceHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

// After a failed write HDF5 keeps a half-closed file in its tables, and its
// clean-up at exit crashes on it (H5F__close_cb). Every file is closed
// explicitly (FieldSeries::close and the destructor), so the library's own
// clean-up at exit is switched off, before the first HDF5 call.
[[maybe_unused]] const bool kNoHdf5CleanupAtExit = H5dont_atexit() >= 0;

// The section of a checkpoint that holds a series (its layout: steps with the units of their arrays).
constexpr const char* kStateTag = "field_series_v2";

int nodesPerCell(CellType t) {
  switch (t) {
    case CellType::Points: return 1;
    case CellType::Triangle: return 3;
    case CellType::Quad: return 4;
    case CellType::Tetra: return 4;
    case CellType::Hexa: return 8;
    case CellType::Line: return 2;
  }
  return 1;
}

// Pairs (x, y) as triples (x, y, 0): the points and vectors of a 2D series, as
// ParaView's filters (Warp By Vector, Glyph) need 3 components.
std::vector<double> withZeroZ(const std::vector<double>& xy) {
  std::vector<double> xyz;
  xyz.reserve(xy.size() / 2 * 3);
  for (std::size_t i = 0; i + 1 < xy.size(); i += 2) xyz.insert(xyz.end(), {xy[i], xy[i + 1], 0.0});
  return xyz;
}

// The array's name in the XDMF, which ParaView and meshio show: the dataset's name and its unit,
// except the integer labels (ids, no unit) and the displacement (the vector Warp By Vector takes),
// whose unit is the dataset's `units` attribute only.
std::string xdmfAttributeName(const std::string& name, const std::string& unit, bool integer) {
  if (integer || name == "displacement") return name;
  return fmt::format("{} [{}]", name, unit);
}

}  // namespace

struct FieldSeries::Impl {
  std::filesystem::path h5path, xdmfpath;
  int dim;
  hid_t file = -1;
  CellType type = CellType::Points;
  std::size_t npoints = 0, ncells = 0;
  bool meshSet = false;
  std::vector<Step> steps;
  std::vector<Attr> meshLabels;  // constant integer point and cell arrays, in every step
  bool open = false;

  // Any failed HDF5 call: an Error naming the file (errno as the failing write left it).
  void check(long long status) const {
    if (status < 0) throwWriteFailure(h5path, errno);
  }
  // The string attribute `key` of dataset `ds` (variable-length UTF-8: h5py reads it as str).
  void writeText(hid_t ds, const char* key, const std::string& value) {
    H5Handle type{H5Tcopy(H5T_C_S1), H5Tclose};
    check(type.id);
    check(H5Tset_size(type.id, H5T_VARIABLE));
    check(H5Tset_cset(type.id, H5T_CSET_UTF8));
    H5Handle space{H5Screate(H5S_SCALAR), H5Sclose};
    check(space.id);
    H5Handle attr{H5Acreate2(ds, key, type.id, space.id, H5P_DEFAULT, H5P_DEFAULT), H5Aclose};
    check(attr.id);
    const char* text = value.c_str();
    check(H5Awrite(attr.id, type.id, &text));
    check(attr.close());
  }
  // Creates dataset `path` (rows x cols) of `fileType`, writes `data` of `memType` into it and
  // gives it the attribute units = `unit` (and names = `note` when not empty).
  void writeArray(const std::string& path, hid_t fileType, hid_t memType, const void* data, std::size_t rows,
                  std::size_t cols, const std::string& unit, const std::string& note = {}) {
    hsize_t dims[2] = {rows, cols};
    H5Handle space{H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose};
    H5Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
    check(space.id);
    check(lcpl.id);
    check(H5Pset_create_intermediate_group(lcpl.id, 1));
    H5Handle ds{H5Dcreate2(file, path.c_str(), fileType, space.id, lcpl.id, H5P_DEFAULT, H5P_DEFAULT), H5Dclose};
    check(ds.id);
    check(H5Dwrite(ds.id, memType, H5S_ALL, H5S_ALL, H5P_DEFAULT, data));
    writeText(ds.id, "units", unit);
    if (!note.empty()) writeText(ds.id, "names", note);
    check(ds.close());
  }
  void write(const std::string& path, const std::vector<double>& v, std::size_t rows, std::size_t cols,
             const std::string& unit) {
    // Never write NaN: a field with a NaN means the solver failed to detect its own divergence.
    for (double x : v)
      if (!std::isfinite(x)) throw SolverError("field " + path + " holds a non-finite value; the run diverged");
    writeArray(path, H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, v.data(), rows, cols, unit);
  }
  // Point coordinates: 3 per point in the file (a 2D series gets z = 0).
  void writePoints(const std::string& path, const std::vector<double>& v, std::size_t count) {
    write(path, dim == 2 ? withZeroZ(v) : v, count, 3, "m");
  }
  void writeInt(const std::string& path, const std::vector<int>& v, std::size_t rows, std::size_t cols,
                const std::string& note = {}) {
    writeArray(path, H5T_STD_I32LE, H5T_NATIVE_INT, v.data(), rows, cols, "1", note);
  }
  void flush() const { check(H5Fflush(file, H5F_SCOPE_GLOBAL)); }
  // Closes the file once (the handle is forgotten first, whatever H5Fclose
  // answers); false when the close failed (the last data did not reach the disk).
  bool close() {
    if (file < 0) return true;
    const hid_t f = file;
    file = -1;
    return H5Fclose(f) >= 0;
  }
  // One array of the current step: a vector of a 2D series is stored with 3 components (z = 0).
  void addArray(const std::string& name, const std::vector<double>& v, int comp, bool cell, const std::string& unit) {
    auto& st = steps.back();
    const std::string ds = fmt::format("/step{:06d}/{}/{}", steps.size() - 1, cell ? "cell" : "point", name);
    const std::size_t count = v.size() / static_cast<std::size_t>(comp);
    const bool planarVector = dim == 2 && comp == 2;
    write(ds, planarVector ? withZeroZ(v) : v, count, planarVector ? 3 : comp, unit);
    st.attrs.push_back(Attr{name, cell, planarVector ? 3 : comp, ds, count, unit});
  }

  std::string topologyXml(std::size_t np) const {
    const std::string h5 = h5path.filename().string();
    const std::size_t n = type == CellType::Points ? np : ncells;
    const int per = nodesPerCell(type);
    const std::string dims = per == 1 ? std::to_string(n) : fmt::format("{} {}", n, per);  // as the dataset's rank
    return fmt::format(
        "<Topology TopologyType=\"{}\" NumberOfElements=\"{}\" NodesPerElement=\"{}\">\n<DataItem Dimensions=\"{}\" "
        "NumberType=\"Int\" Format=\"HDF\">{}:/mesh/cells</DataItem>\n</Topology>\n",
        topologyName(type), n, per, dims, h5);
  }
  std::string attributeXml(const Attr& a) const {
    const char* kind = a.components == 1 ? "Scalar" : a.components == 6 ? "Tensor6" : "Vector";
    return fmt::format(
        "<Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n<DataItem Dimensions=\"{}{}\" "
        "NumberType=\"{}\" Precision=\"{}\" Format=\"HDF\">{}:{}</DataItem>\n</Attribute>\n",
        xdmfAttributeName(a.name, a.unit, a.integer), kind, a.cell ? "Cell" : "Node", a.count,
        a.components == 1 ? "" : fmt::format(" {}", a.components), a.integer ? "Int" : "Float", a.integer ? 4 : 8,
        h5path.filename().string(), a.dataset);
  }
  std::string xdmf() const {
    const std::string h5 = h5path.filename().string();
    std::string s = "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n<Domain>\n"
                    "<Grid Name=\"series\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
    for (std::size_t k = 0; k < steps.size(); ++k) {
      const Step& st = steps[k];
      s += fmt::format("<Grid Name=\"step{}\" GridType=\"Uniform\">\n<Time Value=\"{:.12g}\"/>\n", k, st.time);
      const std::size_t np = st.points.empty() ? npoints : st.npoints;
      s += topologyXml(np);
      s += fmt::format(
          "<Geometry GeometryType=\"XYZ\">\n<DataItem Dimensions=\"{} 3\" NumberType=\"Float\" Precision=\"8\" "
          "Format=\"HDF\">{}:{}</DataItem>\n</Geometry>\n",
          np, h5, st.points.empty() ? "/mesh/points" : st.points);
      for (const auto& a : meshLabels) s += attributeXml(a);
      for (const auto& a : st.attrs) s += attributeXml(a);
      s += "</Grid>\n";
    }
    s += "</Grid>\n</Domain>\n</Xdmf>\n";
    return s;
  }
};

FieldSeries::FieldSeries(std::filesystem::path h5, std::filesystem::path xdmf, int dim) : impl_(new Impl) {
  impl_->h5path = std::move(h5);
  impl_->xdmfpath = std::move(xdmf);
  impl_->dim = dim;
  silenceHdf5Errors();
  if (impl_->h5path.has_parent_path()) std::filesystem::create_directories(impl_->h5path.parent_path());
  impl_->file = H5Fcreate(impl_->h5path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
  impl_->check(impl_->file);
}

FieldSeries::~FieldSeries() { impl_->close(); }

void FieldSeries::close() {
  if (!impl_->close()) throwWriteFailure(impl_->h5path, errno);
}

void FieldSeries::setMesh(const std::vector<double>& points, CellType type, const std::vector<int>& conn) {
  auto& I = *impl_;
  I.type = type;
  I.npoints = points.size() / static_cast<std::size_t>(I.dim);
  I.writePoints("/mesh/points", points, I.npoints);
  if (type == CellType::Points) {  // one Polyvertex cell per point
    std::vector<int> own(I.npoints);
    for (std::size_t p = 0; p < own.size(); ++p) own[p] = static_cast<int>(p);
    I.ncells = I.npoints;
    I.writeInt("/mesh/cells", own, I.ncells, 1);
  } else {
    I.ncells = conn.size() / static_cast<std::size_t>(nodesPerCell(type));
    I.writeInt("/mesh/cells", conn, I.ncells, static_cast<std::size_t>(nodesPerCell(type)));
  }
  I.meshSet = true;
}

void FieldSeries::meshPointLabels(const std::string& name, const std::vector<int>& values, const std::string& legend) {
  auto& I = *impl_;
  if (!I.meshSet || values.size() != I.npoints)
    throw Error(fmt::format("internal: FieldSeries::meshPointLabels got {} values for a mesh of {} points", values.size(),
                            I.npoints));
  const std::string ds = "/mesh/point/" + name;
  I.writeInt(ds, values, values.size(), 1, legend);
  I.meshLabels.push_back(Attr{name, false, 1, ds, values.size(), "1", true});
}

void FieldSeries::meshCellLabels(const std::string& name, const std::vector<int>& values, const std::string& legend) {
  auto& I = *impl_;
  if (!I.meshSet || values.size() != I.ncells)
    throw Error(fmt::format("internal: FieldSeries::meshCellLabels got {} values for a mesh of {} cells", values.size(),
                            I.ncells));
  const std::string ds = "/mesh/cell/" + name;
  I.writeInt(ds, values, values.size(), 1, legend);
  I.meshLabels.push_back(Attr{name, true, 1, ds, values.size(), "1", true});
}

void FieldSeries::beginStep(double time) {
  if (!impl_->meshSet) throw Error("internal: FieldSeries::setMesh must come before the first step");
  impl_->steps.push_back(Step{time, {}, impl_->npoints, {}});
  impl_->open = true;
}

void FieldSeries::stepPoints(const std::vector<double>& points) {
  auto& I = *impl_;
  const std::size_t count = points.size() / static_cast<std::size_t>(I.dim);
  if (count != I.npoints)
    throw Error(fmt::format("internal: FieldSeries::stepPoints got {} points for a mesh of {}", count, I.npoints));
  auto& st = I.steps.back();
  st.points = fmt::format("/step{:06d}/points", I.steps.size() - 1);
  st.npoints = count;
  I.writePoints(st.points, points, count);
}

void FieldSeries::pointData(const std::string& name, const std::vector<double>& v, int comp, const std::string& unit) {
  impl_->addArray(name, v, comp, false, unit);
}

void FieldSeries::cellData(const std::string& name, const std::vector<double>& v, int comp, const std::string& unit) {
  impl_->addArray(name, v, comp, true, unit);
}

void FieldSeries::endStep() {
  auto& I = *impl_;
  I.flush();
  writeFileAtomic(I.xdmfpath, I.xdmf());
  I.open = false;
}

std::size_t FieldSeries::steps() const { return impl_->steps.size(); }
const std::filesystem::path& FieldSeries::xdmfPath() const { return impl_->xdmfpath; }

void FieldSeries::saveState(BinaryWriter& w, const std::filesystem::path& h5copy) const {
  namespace fs = std::filesystem;
  const auto& I = *impl_;
  if (I.open) throw Error("internal: FieldSeries::saveState inside a step");
  I.flush();
  fs::path tmp = h5copy;
  tmp += ".tmp." + std::to_string(::getpid());
  std::error_code ec;
  fs::copy_file(I.h5path, tmp, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::rename(tmp, h5copy, ec);
  if (ec) {
    const int err = ec.value();
    fs::remove(tmp, ec);
    throwWriteFailure(h5copy, err);
  }
  w.tag(kStateTag);
  w.pod(static_cast<std::int32_t>(I.dim));
  w.pod(static_cast<std::int32_t>(I.type));
  w.pod(static_cast<std::uint64_t>(I.npoints));
  w.pod(static_cast<std::uint64_t>(I.ncells));
  w.pod(static_cast<std::uint8_t>(I.meshSet));
  w.pod(static_cast<std::uint64_t>(I.steps.size()));
  for (const Step& st : I.steps) {
    w.pod(st.time);
    w.str(st.points);
    w.pod(static_cast<std::uint64_t>(st.npoints));
    w.pod(static_cast<std::uint64_t>(st.attrs.size()));
    for (const Attr& a : st.attrs) {
      w.str(a.name);
      w.pod(static_cast<std::uint8_t>(a.cell));
      w.pod(static_cast<std::int32_t>(a.components));
      w.str(a.dataset);
      w.pod(static_cast<std::uint64_t>(a.count));
      w.str(a.unit);
    }
  }
}

void FieldSeries::restore(BinaryReader& r, const std::filesystem::path& h5copy) {
  namespace fs = std::filesystem;
  auto& I = *impl_;
  r.tag(kStateTag);
  if (r.pod<std::int32_t>() != I.dim) r.fail("its field series has another dimension than this run's");
  const auto type = r.pod<std::int32_t>();
  if (type < 0 || type > static_cast<std::int32_t>(CellType::Line)) r.fail("unknown cell type in its field series");
  const auto npoints = r.pod<std::uint64_t>(), ncells = r.pod<std::uint64_t>();
  const bool meshSet = r.pod<std::uint8_t>() != 0;
  if (I.meshSet && (npoints != I.npoints || static_cast<CellType>(type) != I.type))
    r.fail(fmt::format("its field series has {} points, this run {}", npoints, I.npoints));
  const auto nsteps = r.pod<std::uint64_t>();
  std::vector<Step> steps;
  for (std::uint64_t k = 0; k < nsteps; ++k) {
    Step st;
    r.pod(st.time);
    st.points = r.str();
    st.npoints = static_cast<std::size_t>(r.pod<std::uint64_t>());
    const auto na = r.pod<std::uint64_t>();
    if (na > 1000) r.fail("a field step with an impossible number of arrays (damaged file)");
    for (std::uint64_t a = 0; a < na; ++a) {
      Attr at;
      at.name = r.str();
      at.cell = r.pod<std::uint8_t>() != 0;
      at.components = r.pod<std::int32_t>();
      at.dataset = r.str();
      at.count = static_cast<std::size_t>(r.pod<std::uint64_t>());
      at.unit = r.str();
      st.attrs.push_back(std::move(at));
    }
    steps.push_back(std::move(st));
  }
  if (!fs::is_regular_file(h5copy))
    throw InputError(SourceLocation{h5copy.string(), 0, 0}, "", "", "is missing (the checkpoint names it)",
                     "the checkpoint folder as the run left it; delete the folder to start afresh");
  I.close();
  std::error_code ec;
  fs::copy_file(h5copy, I.h5path, fs::copy_options::overwrite_existing, ec);
  if (ec) throwWriteFailure(I.h5path, ec.value());
  I.file = H5Fopen(I.h5path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (I.file < 0)
    throw InputError(SourceLocation{h5copy.string(), 0, 0}, "", "", "is not a readable HDF5 file (damaged)",
                     "the checkpoint folder as the run left it; delete the folder to start afresh");
  I.type = static_cast<CellType>(type);
  I.npoints = static_cast<std::size_t>(npoints);
  I.ncells = static_cast<std::size_t>(ncells);
  I.meshSet = meshSet;
  I.steps = std::move(steps);
  I.open = false;
  writeFileAtomic(I.xdmfpath, I.xdmf());
}

}  // namespace needlesim::io
