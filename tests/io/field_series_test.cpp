#include <gtest/gtest.h>
#include <hdf5.h>

#include <sys/resource.h>
#include <sys/wait.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/io/atomic_file.hpp"
#include "needlesim/io/field_series.hpp"
#include "needlesim/results/results_folder.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
namespace fs = std::filesystem;

namespace {
fs::path scratch(const std::string& n) {
  fs::path d = fs::temp_directory_path() / ("needlesim_fields_" + std::to_string(::getpid())) / n;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
std::vector<double> readDataset(const fs::path& h5, const std::string& name) {
  hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  hid_t sp = H5Dget_space(ds);
  hssize_t n = H5Sget_simple_extent_npoints(sp);
  std::vector<double> v(static_cast<std::size_t>(n));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(sp);
  H5Dclose(ds);
  H5Fclose(f);
  return v;
}
// The dataset's shape (rows, columns; columns 1 for a one-dimensional dataset).
std::pair<hsize_t, hsize_t> shapeOf(const fs::path& h5, const std::string& name) {
  hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  hid_t sp = H5Dget_space(ds);
  hsize_t dims[2] = {0, 1};
  H5Sget_simple_extent_dims(sp, dims, nullptr);
  H5Sclose(sp);
  H5Dclose(ds);
  H5Fclose(f);
  return {dims[0], dims[1]};
}
// The string attribute `units` of a dataset ("" when it has none).
std::string unitsOf(const fs::path& h5, const std::string& name) {
  hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  std::string unit;
  if (H5Aexists(ds, "units") > 0) {
    hid_t a = H5Aopen(ds, "units", H5P_DEFAULT);
    hid_t t = H5Aget_type(a);
    char* text = nullptr;
    if (H5Tis_variable_str(t) > 0 && H5Aread(a, t, &text) >= 0 && text) {
      unit = text;
      H5free_memory(text);
    }
    H5Tclose(t);
    H5Aclose(a);
  }
  H5Dclose(ds);
  H5Fclose(f);
  return unit;
}
std::string readText(const fs::path& p) {
  std::ifstream x(p);
  return std::string((std::istreambuf_iterator<char>(x)), {});
}
}  // namespace

TEST(FieldSeries, WritesMeshStepsAndAnXdmfParaViewReads) {
  fs::path d = scratch("quads");
  {
    io::FieldSeries fsr(d / "tissue.h5", d / "tissue.xdmf", 2);
    // Two quads side by side.
    fsr.setMesh({0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1}, io::CellType::Quad, {0, 1, 4, 3, 1, 2, 5, 4});
    for (int k = 0; k < 2; ++k) {
      fsr.beginStep(0.5 * k);
      std::vector<double> u(12, 0.1 * k);
      fsr.pointData("displacement", u, 2, "m");
      fsr.cellData("von_mises", {1.0 * k, 2.0 * k}, 1, "Pa");
      fsr.endStep();
    }
    EXPECT_EQ(fsr.steps(), 2u);
  }
  const fs::path h5 = d / "tissue.h5";
  // 2D vectors and points carry a zero third component, as ParaView's Warp By Vector needs.
  auto u1 = readDataset(h5, "/step000001/point/displacement");
  ASSERT_EQ(u1.size(), 18u);
  EXPECT_EQ(shapeOf(h5, "/step000001/point/displacement"), (std::pair<hsize_t, hsize_t>{6, 3}));
  EXPECT_DOUBLE_EQ(u1[3], 0.1);
  EXPECT_DOUBLE_EQ(u1[4], 0.1);
  EXPECT_DOUBLE_EQ(u1[5], 0.0);
  EXPECT_EQ(readDataset(h5, "/mesh/points"),
            (std::vector<double>{0, 0, 0, 1, 0, 0, 2, 0, 0, 0, 1, 0, 1, 1, 0, 2, 1, 0}));
  auto vm = readDataset(h5, "/step000001/cell/von_mises");
  EXPECT_EQ(vm, (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(unitsOf(h5, "/step000001/point/displacement"), "m");
  EXPECT_EQ(unitsOf(h5, "/step000001/cell/von_mises"), "Pa");
  EXPECT_EQ(unitsOf(h5, "/mesh/points"), "m");
  EXPECT_EQ(unitsOf(h5, "/mesh/cells"), "1");
  const std::string xdmf = readText(d / "tissue.xdmf");
  EXPECT_NE(xdmf.find("TopologyType=\"Quadrilateral\" NumberOfElements=\"2\" NodesPerElement=\"4\""),
            std::string::npos);
  EXPECT_NE(xdmf.find("<Geometry GeometryType=\"XYZ\">\n<DataItem Dimensions=\"6 3\""), std::string::npos);
  EXPECT_NE(xdmf.find("<Time Value=\"0.5\"/>"), std::string::npos);
  EXPECT_NE(xdmf.find("<Attribute Name=\"displacement\" AttributeType=\"Vector\" Center=\"Node\">\n"
                      "<DataItem Dimensions=\"6 3\""),
            std::string::npos);
  EXPECT_NE(xdmf.find("<Attribute Name=\"von_mises [Pa]\" AttributeType=\"Scalar\" Center=\"Cell\">"),
            std::string::npos);
  EXPECT_NE(xdmf.find("tissue.h5:/step000001/point/displacement"), std::string::npos);
}

// ParaView's XDMF3 reader needs NodesPerElement for a polyline (else it aborts the file).
TEST(FieldSeries, APolylineNamesItsNodesPerElement) {
  fs::path d = scratch("line");
  {
    io::FieldSeries fsr(d / "needle.h5", d / "needle.xdmf", 2);
    fsr.setMesh({0, 0, 1, 0, 2, 0}, io::CellType::Line, {0, 1, 1, 2});
    fsr.beginStep(0.0);
    fsr.stepPoints({0, 1, 1, 1, 2, 1});
    fsr.endStep();
  }
  const std::string xdmf = readText(d / "needle.xdmf");
  EXPECT_NE(xdmf.find("<Topology TopologyType=\"Polyline\" NumberOfElements=\"2\" NodesPerElement=\"2\">\n"
                      "<DataItem Dimensions=\"2 2\" NumberType=\"Int\" Format=\"HDF\">needle.h5:/mesh/cells</DataItem>"),
            std::string::npos)
      << xdmf;
  EXPECT_EQ(readDataset(d / "needle.h5", "/step000000/points"), (std::vector<double>{0, 1, 0, 1, 1, 0, 2, 1, 0}));
}

// Particles get one Polyvertex cell each (without connectivity ParaView shows 0 cells).
TEST(FieldSeries, ParticlesAreOnePolyvertexEach) {
  fs::path d = scratch("particles");
  {
    io::FieldSeries fsr(d / "particles.h5", d / "particles.xdmf", 3);
    fsr.setMesh({0, 0, 0, 1, 0, 0, 0, 1, 0}, io::CellType::Points, {});
    fsr.beginStep(0.25);
    fsr.pointData("displacement", std::vector<double>(9, 0.5), 3, "m");
    fsr.endStep();
    EXPECT_THROW(fsr.stepPoints({0, 0, 0}), Error);  // as many points as the mesh
  }
  EXPECT_EQ(readDataset(d / "particles.h5", "/mesh/cells"), (std::vector<double>{0, 1, 2}));
  const std::string xdmf = readText(d / "particles.xdmf");
  EXPECT_NE(xdmf.find("<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"3\" NodesPerElement=\"1\">\n"
                      "<DataItem Dimensions=\"3\" NumberType=\"Int\" Format=\"HDF\">particles.h5:/mesh/cells</DataItem>"),
            std::string::npos)
      << xdmf;
  EXPECT_NE(xdmf.find("<DataItem Dimensions=\"3 3\" NumberType=\"Float\" Precision=\"8\" "
                      "Format=\"HDF\">particles.h5:/step000000/point/displacement</DataItem>"),
            std::string::npos);
}

// A region id per cell (ParaView's Threshold picks the tumour by it): an int32 dataset with the
// legend, shown at every step under its bare name; a count other than the cells' is refused.
TEST(FieldSeries, CellLabelsAreIntegersShownAtEveryStep) {
  fs::path d = scratch("cell_labels");
  {
    io::FieldSeries fsr(d / "tissue.h5", d / "tissue.xdmf", 2);
    fsr.setMesh({0, 0, 1, 0, 2, 0, 0, 1, 1, 1, 2, 1}, io::CellType::Quad, {0, 1, 4, 3, 1, 2, 5, 4});
    EXPECT_THROW(fsr.meshCellLabels("region", {0, 1, 1}, "0 gland, 1 tumour"), Error);
    fsr.meshCellLabels("region", {0, 1}, "0 gland, 1 tumour");
    for (int k = 0; k < 2; ++k) {
      fsr.beginStep(0.5 * k);
      fsr.pointData("displacement", std::vector<double>(12, 0.1), 2, "m");
      fsr.endStep();
    }
  }
  EXPECT_EQ(readDataset(d / "tissue.h5", "/mesh/cell/region"), (std::vector<double>{0, 1}));
  EXPECT_EQ(unitsOf(d / "tissue.h5", "/mesh/cell/region"), "1");
  const std::string xdmf = readText(d / "tissue.xdmf");
  const std::string label =
      "<Attribute Name=\"region\" AttributeType=\"Scalar\" Center=\"Cell\">\n<DataItem Dimensions=\"2\" "
      "NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">tissue.h5:/mesh/cell/region</DataItem>";
  const auto first = xdmf.find(label);
  ASSERT_NE(first, std::string::npos) << xdmf;
  EXPECT_NE(xdmf.find(label, first + 1), std::string::npos);  // in both steps
  EXPECT_EQ(xdmf.find("/step000000/points"), std::string::npos);  // the reference points at every step
}

TEST(FieldSeries, RefusesToWriteNaN) {
  fs::path d = scratch("nan");
  io::FieldSeries fsr(d / "p.h5", d / "p.xdmf", 3);
  fsr.setMesh({0, 0, 0, 1, 1, 1}, io::CellType::Points, {});
  fsr.beginStep(0.0);
  EXPECT_THROW(fsr.pointData("v", {1.0, NAN}, 1, "Pa"), SolverError);
}

TEST(ResultsFolder, AStoppedRunKeepsItsResultsMarkedAsStopped) {
  fs::path d = scratch("stopped");
  Scenario sc = scenario::defaultScenario();
  {
    io::ResultsFolder folder(sc, d / "run");
    auto* f = folder.fields("tissue", 2);
    ASSERT_NE(f, nullptr);
    f->setMesh({0, 0, 1, 0, 0, 1}, io::CellType::Triangle, {0, 1, 2});
    f->beginStep(0.0);
    f->pointData("u", {0, 0, 0, 0, 0, 0}, 2, "m");
    f->endStep();
    folder.result("x", 1.0, "m", "a value");
    folder.commit(false, 0.1, "time step too large for the mesh: reduce model.time_step");
  }
  nlohmann::json s = nlohmann::json::parse(std::ifstream(d / "run" / "summary.json"));
  EXPECT_EQ(s["status"], "stopped");
  EXPECT_NE(s["stopped_because"].get<std::string>().find("time step"), std::string::npos);
  EXPECT_TRUE(fs::exists(d / "run" / "tissue.xdmf"));
  EXPECT_TRUE(fs::exists(d / "run" / "tissue.h5"));
  // No staging folder is left behind.
  for (auto& e : fs::directory_iterator(d)) EXPECT_EQ(e.path().filename(), "run");
}

namespace {
// Runs `body` in a child process whose files may grow to `limit` bytes (a full
// disk: writes past it fail with EFBIG, SIGXFSZ ignored). The child ends with
// exit(), so HDF5's and the C library's exit-time clean-up run as in needlesim.
// Returns the child's exit code, or -signal when a signal ended it.
int withFileSizeLimit(rlim_t limit, const std::function<int()>& body) {
  const pid_t child = fork();
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    rlimit lim{limit, limit};
    setrlimit(RLIMIT_FSIZE, &lim);
    std::exit(body());
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -WTERMSIG(status);
}

// Status of a write that had to fail: 0 when it threw an Error whose message names `file`
// and says "disk full / write failed", 1 when it did not throw, 2 for another message.
int expectWriteFailure(const std::string& file, const std::function<void()>& write) {
  try {
    write();
  } catch (const Error& e) {
    const std::string m = e.what();
    return m.find(file) != std::string::npos && m.find("disk full / write failed: File too large") != std::string::npos
               ? 0
               : 2;
  }
  return 1;
}
}  // namespace

TEST(FieldSeries, AFullDiskIsAnErrorNamingTheFileWithoutACrashAtExit) {
  fs::path d = scratch("full");
  const int code = withFileSizeLimit(64 * 1024, [&] {
    return expectWriteFailure("particles.h5", [&] {
      io::FieldSeries fsr(d / "particles.h5", d / "particles.xdmf", 3);
      std::vector<double> points(3 * 1000, 0.5);
      fsr.setMesh(points, io::CellType::Points, {});
      for (int k = 0; k < 100; ++k) {
        fsr.beginStep(k * 0.1);
        fsr.stepPoints(points);
        fsr.endStep();
      }
      fsr.close();
    });
  });
  EXPECT_EQ(code, 0) << "1: no error raised, 2: another message, < 0: killed by signal " << -code;
}

TEST(AtomicFile, AFullDiskIsAnErrorNamingTheFileAndLeavesNoTemporary) {
  fs::path d = scratch("atomic_full");
  const int code = withFileSizeLimit(1024, [&] {
    return expectWriteFailure("forces.csv", [&] { io::writeFileAtomic(d / "forces.csv", std::string(4096, 'x')); });
  });
  EXPECT_EQ(code, 0) << "1: no error raised, 2: another message, < 0: killed by signal " << -code;
  EXPECT_TRUE(fs::is_empty(d));
}

TEST(ResultsFolder, WarningsGoToSummaryAndTheTopOfTheReport) {
  fs::path d = scratch("warnings");
  Scenario sc = scenario::defaultScenario();
  {
    io::ResultsFolder folder(sc, d / "run");
    folder.note("an ordinary note");
    folder.warning("Kinetic energy exceeded 10 % of the internal energy: the run was not quasi-static <x>");
    folder.commit(false, 0.1);
  }
  nlohmann::json s = nlohmann::json::parse(std::ifstream(d / "run" / "summary.json"));
  ASSERT_EQ(s["warnings"].size(), 1u);
  EXPECT_NE(s["warnings"][0].get<std::string>().find("not quasi-static"), std::string::npos);
  EXPECT_EQ(s["notes"].size(), 1u);
  std::ifstream in(d / "run" / "report.html");
  const std::string html((std::istreambuf_iterator<char>(in)), {});
  const auto box = html.find("<div class=\"warnings\"");
  ASSERT_NE(box, std::string::npos);
  EXPECT_LT(box, html.find("<table>"));  // above the results
  EXPECT_NE(html.find("not quasi-static &lt;x&gt;", box), std::string::npos);
}

TEST(ResultsFolder, OnlyAFolderWithANeedlesimSummaryIsAResultsFolder) {
  fs::path d = scratch("kinds");
  Scenario sc = scenario::defaultScenario();
  {
    io::ResultsFolder folder(sc, d / "run/");  // a trailing separator names the same folder
    EXPECT_EQ(folder.target(), d / "run");
    folder.commit(false, 0.1);
  }
  EXPECT_TRUE(io::isResultsFolder(d / "run"));
  fs::create_directories(d / "thesis");
  std::ofstream(d / "thesis" / "thesis.tex") << "\\documentclass{report}";
  std::ofstream(d / "thesis" / "summary.json") << "{\"status\": \"draft\"}";  // not needlesim's
  EXPECT_FALSE(io::isResultsFolder(d / "thesis"));
  EXPECT_EQ(io::describeContents(d / "thesis"), "a folder holding summary.json, thesis.tex");
  {
    io::ResultsFolder folder(sc, d / "thesis");
    EXPECT_THROW(folder.commit(true, 0.1), Error);  // --overwrite does not reach a user's folder
  }
  EXPECT_TRUE(fs::exists(d / "thesis" / "thesis.tex"));
}

TEST(MemorySink, KeepsWarningsApartFromNotes) {
  MemorySink sink;
  ResultSink& asSink = sink;
  asSink.note("a note");
  asSink.warning("the run was not quasi-static");
  EXPECT_EQ(sink.notes, std::vector<std::string>{"a note"});
  EXPECT_EQ(sink.warnings, std::vector<std::string>{"the run was not quasi-static"});
}
