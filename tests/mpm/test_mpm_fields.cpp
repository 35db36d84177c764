// The mpm engine's field series (docs/results.md "Field files"): particles as one
// Polyvertex each, with the region (layer or inclusion) of each, and the rigid needle's
// surface at the same times, placed where forces.csv puts the tip.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;
namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t i = text.find(what); i != std::string::npos; i = text.find(what, i + 1)) ++n;
  return n;
}

std::vector<double> readDataset(const fs::path& h5, const std::string& name) {
  const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t sp = H5Dget_space(ds);
  std::vector<double> v(static_cast<std::size_t>(std::max<hssize_t>(0, H5Sget_simple_extent_npoints(sp))));
  if (!v.empty()) H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(sp);
  H5Dclose(ds);
  H5Fclose(f);
  return v;
}

// An int32 dataset and its string attribute `attribute` (empty when absent).
std::vector<int> readInts(const fs::path& h5, const std::string& name, const char* attribute, std::string& text) {
  const hid_t f = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  std::vector<int> v;
  if (ds >= 0) {
    const hid_t sp = H5Dget_space(ds);
    v.resize(static_cast<std::size_t>(std::max<hssize_t>(0, H5Sget_simple_extent_npoints(sp))));
    if (!v.empty()) H5Dread(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
    H5Sclose(sp);
    if (H5Aexists(ds, attribute) > 0) {
      const hid_t a = H5Aopen(ds, attribute, H5P_DEFAULT);
      const hid_t type = H5Aget_type(a);
      char* value = nullptr;
      H5Aread(a, type, &value);
      text = value ? value : "";
      H5free_memory(value);
      H5Tclose(type);
      H5Aclose(a);
    }
    H5Dclose(ds);
  }
  H5Fclose(f);
  return v;
}

fs::path freshDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

// The quick example 2 mm deep: the needle series has a step for every particle step, and its
// most distal point (the cone's apex; the insertion axis is x) is the tip of forces.csv's last
// row, in the same tissue frame as the particles.
TEST(MpmFields, TheNeedleSeriesFollowsTheTipOfForcesCsv) {
  const fs::path dir = fs::temp_directory_path() / ("needlesim_mpm_fields_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::string text = slurp(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/mpm/quick_needle_block.yaml");
  text.replace(text.find("insert: {to: 5 mm"), 17, "insert: {to: 2 mm");
  std::ofstream(dir / "quick.yaml") << text;
  RunOptions o;
  o.progress = false;
  runScenario(scenario::readFile(dir / "quick.yaml"), dir / "out", false, o);

  const std::string particles = slurp(dir / "out" / "particles.xdmf"), needle = slurp(dir / "out" / "needle.xdmf");
  const std::size_t steps = count(particles, "<Time ");
  ASSERT_GE(steps, 3u);
  EXPECT_EQ(count(needle, "<Time "), steps);
  EXPECT_NE(needle.find("<Topology TopologyType=\"Triangle\""), std::string::npos);
  EXPECT_NE(particles.find("<Topology TopologyType=\"Polyvertex\" NumberOfElements=\"2304\" NodesPerElement=\"1\">"),
            std::string::npos);

  const std::vector<double> last = readDataset(dir / "out" / "needle.h5", fmt::format("/step{:06d}/points", steps - 1));
  ASSERT_FALSE(last.empty());
  std::size_t apex = 0;
  for (std::size_t i = 0; i < last.size(); i += 3)
    if (last[i] > last[apex]) apex = i;
  const io::CsvData forces = io::readCsv(dir / "out" / "forces.csv");
  for (int c = 0; c < 3; ++c) {
    const std::string column = std::string("tip_") + "xyz"[c];
    EXPECT_NEAR(last[apex + static_cast<std::size_t>(c)], forces.col(forces.find({column})).back(), 1e-9) << column;
  }
  EXPECT_NEAR(last[apex], 2e-3, 1e-9);  // the profile's end depth
  // The particles in the same (tissue) frame: the block 8 x 6 x 6 mm, the entry face's centre at 0.
  const std::vector<double> x0 = readDataset(dir / "out" / "particles.h5", "/mesh/points");
  double lo[3] = {1, 1, 1}, hi[3] = {-1, -1, -1};
  for (std::size_t i = 0; i < x0.size(); ++i) {
    lo[i % 3] = std::min(lo[i % 3], x0[i]);
    hi[i % 3] = std::max(hi[i % 3], x0[i]);
  }
  EXPECT_NEAR(lo[0] + hi[0], 8e-3, 1e-12);  // x from 0 to 8 mm, the points half a spacing inside
  EXPECT_NEAR(lo[1] + hi[1], 0.0, 1e-12);   // y and z centred
  EXPECT_NEAR(lo[2] + hi[2], 0.0, 1e-12);
  fs::remove_all(dir);
}

// Two layers (front 3 mm, back 5 mm) and a sphere of radius 1.5 mm 5 mm deep in the back one:
// every particle's region is 0, 1 or 2 by where it starts, the same array at every step, named.
TEST(MpmFields, EveryParticleCarriesItsRegion) {
  const fs::path dir = freshDir("needlesim_mpm_regions");
  std::string text = slurp(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/mpm/quick_needle_block.yaml");
  text.replace(text.find("insert: {to: 5 mm"), 17, "insert: {to: 1 mm");
  const std::string material = "{law: fung, mu: 10 kPa, gamma: 1.0, nu: 0.475, density: 1000 kg/m^3}";
  const std::size_t from = text.find("  material: {name: pva"), to = text.find("\nneedle:");
  text.replace(from, to - from,
               "  layers:\n"
               "    - {name: front, thickness: 3 mm, material: " + material + ", friction: {coefficient: 0.255}}\n"
               "    - {name: back, thickness: 5 mm, material: " + material + ", friction: {coefficient: 0.255}}\n"
               "  inclusions:\n"
               "    - {name: tumour, depth: 5 mm, radius: 1.5 mm, material: " + material + "}\n");
  std::ofstream(dir / "regions.yaml") << text;
  RunOptions o;
  o.progress = false;
  runScenario(scenario::readFile(dir / "regions.yaml"), dir / "out", false, o);

  std::string names, units;
  const std::vector<int> region = readInts(dir / "out" / "particles.h5", "/mesh/point/region", "names", names);
  readInts(dir / "out" / "particles.h5", "/mesh/point/region", "units", units);
  const std::vector<double> x0 = readDataset(dir / "out" / "particles.h5", "/mesh/points");
  ASSERT_EQ(region.size() * 3, x0.size());
  EXPECT_EQ(names, "0 front, 1 back, 2 tumour");
  EXPECT_EQ(units, "1");
  std::size_t counts[3] = {0, 0, 0};
  for (std::size_t p = 0; p < region.size(); ++p) {
    const double x = x0[3 * p], y = x0[3 * p + 1], z = x0[3 * p + 2];
    const double r = std::sqrt((x - 5e-3) * (x - 5e-3) + y * y + z * z);
    const int expected = r <= 1.5e-3 ? 2 : x < 3e-3 ? 0 : 1;
    ASSERT_EQ(region[p], expected) << "point " << p << " at x = " << x << " m, " << r << " m from the centre";
    ++counts[expected];
  }
  EXPECT_GT(counts[0], 0u);
  EXPECT_GT(counts[1], 0u);
  EXPECT_GT(counts[2], 0u);
  const std::string particles = slurp(dir / "out" / "particles.xdmf");
  const std::size_t steps = count(particles, "<Time ");
  ASSERT_GE(steps, 2u);
  EXPECT_EQ(count(particles, "<Attribute Name=\"region\" AttributeType=\"Scalar\" Center=\"Node\">\n<DataItem "
                             "Dimensions=\"2304\" NumberType=\"Int\" Precision=\"4\" Format=\"HDF\">"
                             "particles.h5:/mesh/point/region</DataItem>"),
            steps);
  fs::remove_all(dir);
}
