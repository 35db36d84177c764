// A crack path other than the straight line, with the rigid needle following it (follow-the-leader,
// explicit/path_needle.hpp; docs/models/cohesive.md "Crack path"; numbers in docs/validation/cohesive.md
// "Crack path"): a straight path given as points equals the default run, a circular arc dissipates G_c
// times the cut length, opens the tissue along the arc, pushes the tissue towards the outside of the
// curve and balances the needle's work; bad path inputs are rejected with file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/explicit/path_from_scenario.hpp"
#include "needlesim/engines/explicit/path_needle.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/scenario/reader.hpp"

using namespace needlesim;

namespace {
// 2D bevel insertion with the cohesive seam (the NeedleEnergy scenario of test_cohesive_energy.cpp)
std::string yaml(const std::string& path, double depth, double mu = 0.3, const std::string& extra = "") {
  return std::string(R"(
name: path_2d
tissue:
  block: {length: 10 mm, width: 16 mm, height: 10 mm}
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: )") + std::to_string(mu) + R"(}
  interaction: {toughness: 10 J/m^2}
needle: {outer_diameter: 2 mm, length: 30 mm, bevel_angle: 45 deg, tip: bevel, youngs_modulus: 200 GPa}
insertion:
  entry_angle: 90 deg
  start_depth: -0.5 mm
  profile:
    - insert: {to: )" + std::to_string(depth * 1e3) + R"( mm, speed: 10 mm/s}
model:
  engine: explicit
  explicit:
    dimension: 2d
    element: quad4
    element_size: 0.5 mm
    max_element_size: 2 mm
    core_width: 4 mm
    mass_scaling: 15
    contact_penalty: 0.4
    fixed_contact_stiffness: true
)" + extra + R"(    cohesive:
      enable: true
      strength: 20 kPa
)" + path + R"(output: {interval: 10 ms}
)";
}
double res(const MemorySink& m, const char* k) { return m.results.at(k).value; }
MemorySink run(const std::string& text) { return runInMemory(scenario::readText(text, "<path>")); }
// mean of a CSV column over the rows with depth in [d0, d1]
double meanOver(const MemorySink& m, const char* table, const char* col, double d0, double d1) {
  const auto& t = m.tables.at(table);
  const auto depth = t.column("depth"), v = t.column(col);
  double s = 0;
  int n = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (depth[i] >= d0 && depth[i] <= d1) s += v[i], ++n;
  return n ? s / n : 0.0;
}
std::string arc(double radiusMm) { return "      path: arc\n      path_radius: " + std::to_string(radiusMm) + " mm\n"; }
}  // namespace

// The straight path given as two points runs the path needle (local frames, per-node tangents, the
// drive force for the work) and the morph of the seam by zero: the same run as the default straight
// needle, every recorded force and energy to round-off.
TEST(PathNeedle, StraightPathGivenAsPointsEqualsTheDefaultRun) {
  MemorySink s = run(yaml("", 3e-3));
  MemorySink p = run(yaml("      path: points\n      path_points: [{x: 0 mm, y: 0 mm}, {x: 10 mm, y: 0 mm}]\n", 3e-3));
  const std::pair<const char*, const char*> columns[] = {
      {"forces", "depth"},           {"forces", "force_total"},          {"forces", "force_lateral"},
      {"forces", "force_tip"},       {"seam", "cohesive_dissipation"},   {"energy", "needle_work"},
      {"energy", "friction_dissipation"}, {"energy", "needle_energy_balance"}};
  for (const auto& [table, col] : columns) {
    const auto a = s.tables.at(table).column(col), b = p.tables.at(table).column(col);
    ASSERT_EQ(a.size(), b.size()) << col;
    double scale = 1e-300, diff = 0;
    for (std::size_t i = 0; i < a.size(); ++i) scale = std::max(scale, std::abs(a[i])), diff = std::max(diff, std::abs(a[i] - b[i]));
    std::printf("%-22s max |path - default| = %.3g of max %.4g\n", col, diff, scale);
    EXPECT_LE(diff, 1e-9 * scale) << col;
  }
  EXPECT_GT(res(s, "cracked_length"), 1e-3);  // it cut
}

// Circular arcs of radius 30 mm curving towards +y and -y, 6 mm deep, wall friction 0.3.
class PathNeedleArc : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    straight_ = new MemorySink(run(yaml("", 6e-3)));
    up_ = new MemorySink(run(yaml(arc(30), 6e-3)));
    down_ = new MemorySink(run(yaml(arc(-30), 6e-3)));
  }
  static void TearDownTestSuite() {
    delete straight_;
    delete up_;
    delete down_;
  }
  static MemorySink *straight_, *up_, *down_;
};
MemorySink *PathNeedleArc::straight_ = nullptr, *PathNeedleArc::up_ = nullptr, *PathNeedleArc::down_ = nullptr;

// D = int Y dd per pair: a fully damaged pair has dissipated exactly G_c x its (arc) length (the exact
// softening integral, cohesive.cpp), a pair in the process zone (0 < d < 1) between 0 and G_c x its length.
// So G_c x cracked area <= D <= G_c x (cracked + process-zone area): the cut length along the arc
// accounts for the dissipation up to the process zone, which is the tolerance.
TEST_F(PathNeedleArc, DissipatesGcTimesCutLength) {
  const double Gc = 10.0;
  for (const MemorySink* m : {up_, down_}) {
    const double D = res(*m, "cohesive_dissipation"), GcA = res(*m, "fracture_energy_of_crack"),
                 proc = Gc * res(*m, "process_zone_area");
    std::printf("arc: D %.5g J, G_c x cut %.5g J (cut %.3f mm along the arc), G_c x process zone %.3g J, "
                "D / (G_c A) %.4f\n",
                D, GcA, res(*m, "cracked_length") * 1e3, proc, D / GcA);
    EXPECT_GT(res(*m, "cracked_length"), 4e-3);  // the seam opened behind the tip along the arc
    EXPECT_GE(D, GcA * (1 - 1e-9));
    EXPECT_LE(D, (GcA + proc) * (1 + 1e-9));
  }
  // the same cut, as far as the straight needle's (the arc is only 0.3 % longer than its chord here)
  EXPECT_NEAR(res(*up_, "cohesive_dissipation") / res(*straight_, "cohesive_dissipation"), 1.0, 0.1);
  EXPECT_NEAR(res(*down_, "cohesive_dissipation") / res(*straight_, "cohesive_dissipation"), 1.0, 0.1);
}

// Behind the heel every wall-side lip lies on its side of the arc and every bevel-side lip on the other,
// each about one needle radius from the axis path (the shaft sits in the opened crack along the arc).
TEST_F(PathNeedleArc, OpensTheTissueAlongTheArc) {
  const double R = 1e-3;
  for (const MemorySink* m : {up_, down_}) {
    std::printf("arc lips: %g pairs, wall side mean %.4f mm (max %.4f), bevel side mean %.4f mm (min %.4f)\n",
                res(*m, "path_lip_pairs"), res(*m, "path_lip_offset_wall_side") * 1e3,
                res(*m, "path_lip_offset_wall_side_max") * 1e3, res(*m, "path_lip_offset_bevel_side") * 1e3,
                res(*m, "path_lip_offset_bevel_side_min") * 1e3);
    EXPECT_GE(res(*m, "path_lip_pairs"), 4);
    EXPECT_LT(res(*m, "path_lip_offset_wall_side_max"), 0.0);
    EXPECT_GT(res(*m, "path_lip_offset_bevel_side_min"), 0.0);
    // within 10 % of R: the penalty lets a lip into the needle by a few % of R; more would be a lip
    // pushed to the wrong radius (an axis off the arc by 0.1 mm shifts both means by 0.1 R)
    EXPECT_NEAR(res(*m, "path_lip_offset_wall_side"), -R, 0.1 * R);
    EXPECT_NEAR(res(*m, "path_lip_offset_bevel_side"), R, 0.1 * R);
  }
}

// The tissue bent around the curved shaft pushes back towards the centre of curvature: the lateral force on
// the needle (along the tip's lateral, + towards the bevel side = +y at the entry) rises above the straight needle's for the arc
// curving towards +y and falls below it for the arc curving towards -y, i.e. the needle pushes the tissue
// towards the outside of the curve.
TEST_F(PathNeedleArc, LateralForcePushesTheTissueTowardsTheOutside) {
  const double f0 = meanOver(*straight_, "forces", "force_lateral", 2e-3, 6e-3),
               fu = meanOver(*up_, "forces", "force_lateral", 2e-3, 6e-3),
               fd = meanOver(*down_, "forces", "force_lateral", 2e-3, 6e-3);
  std::printf("mean lateral force on the needle 2-6 mm: straight %.4g N, arc +y %.4g N, arc -y %.4g N; axial %.4g / "
              "%.4g / %.4g N\n",
              f0, fu, fd, meanOver(*straight_, "forces", "force_total", 2e-3, 6e-3),
              meanOver(*up_, "forces", "force_total", 2e-3, 6e-3), meanOver(*down_, "forces", "force_total", 2e-3, 6e-3));
  EXPECT_GT(fu - f0, 0.1 * std::abs(f0));
  EXPECT_LT(fd - f0, -0.1 * std::abs(f0));
}

// Needle work (reaction along the local tangents x speed) = kinetic + internal + cohesive + friction +
// penalty within the 2 % of NeedleEnergy.CohesiveInsertionWithFrictionBalancesNeedleWork (same scenario).
TEST_F(PathNeedleArc, BalancesTheNeedleWork) {
  for (const MemorySink* m : {up_, down_}) {
    std::printf("arc: needle work %.4g J, friction %.4g J, needle balance error %.4f, body balance %.2g\n",
                res(*m, "needle_work"), res(*m, "friction_dissipation"), res(*m, "needle_energy_balance_error"),
                res(*m, "energy_balance_error"));
    EXPECT_GT(res(*m, "friction_dissipation"), 0.1 * res(*m, "needle_work"));
    EXPECT_LT(res(*m, "needle_energy_balance_error"), 0.02);
    EXPECT_LT(res(*m, "energy_balance_error"), 1e-9);
  }
}

// The path's geometry (path_needle.cpp): on a finely sampled circle of radius 30 mm the nearest station
// of a point at distance r from the circle is its arc length, and its offset is the circle of radius
// 30 mm - d. Tolerance: a point at distance r projects onto a chord whose direction differs from the
// circle's by up to (ds + ds_in) / (2 R_c) (ds = 0.1 mm the resampling, ds_in = 0.075 mm the given
// points' spacing), so its station is off by up to r (ds + ds_in) / (2 R_c) (2 um at r = 0.7 mm).
TEST(PathNeedle, ArcStationsAndOffsets) {
  const double Rc = 30e-3, ds = 0.1e-3;
  std::vector<Eigen::Vector2d> pts;
  for (int k = 0; k <= 200; ++k) {
    const double phi = 0.5 * k / 200.0;
    pts.emplace_back(Rc * std::sin(phi), Rc * (1 - std::cos(phi)));
  }
  explicit_fe::NeedlePath path(pts, 5e-3, 5e-3, ds);
  EXPECT_NEAR(path.begin(), -5e-3, 1e-12);
  for (double s : {1e-3, 4e-3, 9.3e-3}) {
    const double phi = s / Rc;
    const Eigen::Vector2d on(Rc * std::sin(phi), Rc * (1 - std::cos(phi))), nrm(-std::sin(phi), std::cos(phi));
    for (double r : {-1e-3, 0.0, 0.7e-3})
      EXPECT_NEAR(path.station(on + r * nrm), s, std::abs(r) * (ds + 0.075e-3) / (2 * Rc) + 1e-7) << s << " " << r;
    EXPECT_NEAR((path.point(s) - on).norm(), 0.0, 1e-6);
    EXPECT_NEAR(path.tangent(s).dot(Eigen::Vector2d(std::cos(phi), std::sin(phi))), 1.0, 1e-6);
  }
  // before the first point: the straight extension along the first chord (turned by 1.25 mrad here)
  EXPECT_NEAR(path.station(Eigen::Vector2d(-2e-3, 0.3e-3)), -2e-3 + 0.3e-3 * 1.25e-3, 1e-8);
  for (const auto& q : path.offset(-1e-3))
    if (q.x() > 0.5e-3 && q.x() < 10e-3) EXPECT_NEAR((q - Eigen::Vector2d(0, Rc)).norm(), Rc + 1e-3, 2e-6);
}

// The needle placed on the arc: its tip pose is the path's point and tangent, and its ParaView outline (the
// bent shaft) lies on the two offsets +-R of the path inside the block (bevel points between them).
TEST(PathNeedle, NeedleOnTheArcAndItsOutline) {
  const double Rc = 30e-3, R = 1e-3;
  std::vector<Eigen::Vector2d> pts;
  for (int k = 0; k <= 100; ++k) pts.emplace_back(Rc * std::sin(0.5 * k / 100), Rc * (1 - std::cos(0.5 * k / 100)));
  explicit_fe::RigidNeedle nd;
  nd.shape.radius = R;
  nd.shape.length = 20e-3;
  nd.shape.tipAngle = M_PI / 4;
  nd.shape.tip = TipType::Bevel;
  nd.path = std::make_shared<explicit_fe::NeedlePath>(pts, 25e-3, 5e-3, 0.05e-3);
  nd.pathSide = 1;
  explicit_fe::placeOnPath(nd, 9e-3);
  const double phi = 9e-3 / Rc;
  EXPECT_NEAR((nd.pose.tip - Eigen::Vector3d(Rc * std::sin(phi), Rc * (1 - std::cos(phi)), 0)).norm(), 0.0, 1e-6);
  EXPECT_NEAR(nd.pose.axis.dot(Eigen::Vector3d(std::cos(phi), std::sin(phi), 0)), 1.0, 1e-6);
  EXPECT_NEAR(nd.pose.bevelSide.dot(Eigen::Vector3d(-std::sin(phi), std::cos(phi), 0)), 1.0, 1e-6);
  const auto m = explicit_fe::pathNeedleOutline2D(nd, 40);
  ASSERT_EQ(m.points.size(), 3u * 82);
  for (std::size_t i = 0; i < m.points.size() / 3; ++i) {
    const Eigen::Vector2d q(m.points[3 * i], m.points[3 * i + 1]);
    if (q.x() < 0.1e-3) continue;  // the shaft before the entry lies on the straight extension
    const double r = (q - Eigen::Vector2d(0, Rc)).norm();  // distance from the centre of curvature
    EXPECT_LE(std::abs(r - Rc), R + 1e-6) << i;
    if (i <= 40 || i >= 42) EXPECT_NEAR(std::abs(r - Rc), R, 1e-6) << i;  // walls (and the heel, sharp point)
  }
}

// path: steering takes the kinematic bevel-tip model's path (seed 002; engines/steering): with
// model.steering.curvature 20 1/m a circle of radius 50 mm towards the sharp side (-y at bevel
// orientation 0, +y at 180 deg); without a curvature, the beam-on-foundation curvature of the tip
// loads, also towards the sharp side.
TEST(PathNeedle, SteeringPathCurvesTowardsTheSharpSide) {
  auto steer = [](const std::string& orient, const std::string& steering) {
    std::string t = yaml("      path: steering\n", 6e-3);
    const std::string ea = "  entry_angle: 90 deg";
    t.replace(t.find(ea), ea.size(), ea + "\n  bevel_orientation: " + orient);
    t.replace(t.find("  explicit:"), 11, steering + "  explicit:");
    return explicit_fe::needleAxisPath(scenario::readText(t, "<steer>"), 0.1e-3);
  };
  for (const char* o : {"0 deg", "180 deg"}) {
    const auto p = steer(o, "  steering: {curvature: 20 1/m}\n");
    const double sgn = std::string(o) == "0 deg" ? -1.0 : 1.0, Rc = 0.05;
    ASSERT_GT(p.points.size(), 10u);
    for (const auto& q : p.points) EXPECT_NEAR(q.y(), sgn * (Rc - std::sqrt(Rc * Rc - q.x() * q.x())), 1e-9) << o;
    EXPECT_NEAR(p.points.back().x(), Rc * std::sin(6e-3 / Rc), 1e-9);  // up to the planned insertion
  }
  const auto b = steer("0 deg", "");
  std::printf("steering path from the tip loads: %zu points, lateral %.4g mm at %.3g mm; %s\n", b.points.size(),
              b.points.back().y() * 1e3, b.points.back().x() * 1e3, b.note.c_str());
  EXPECT_LT(b.points.back().y(), 0.0);
}

// A whole run on the steering path (curvature 20 1/m) cuts along it and opens the tissue on both sides.
TEST(PathNeedle, SteeringPathRun) {
  std::string t = yaml("      path: steering\n", 6e-3);
  t.replace(t.find("  explicit:"), 11, "  steering: {curvature: 20 1/m}\n  explicit:");
  MemorySink m = run(t);
  std::printf("steering path run: cut %.3f mm, D / (G_c A) %.4f, lips %.4f / %.4f mm, needle balance %.4f\n",
              res(m, "cracked_length") * 1e3, res(m, "cohesive_dissipation") / res(m, "fracture_energy_of_crack"),
              res(m, "path_lip_offset_wall_side") * 1e3, res(m, "path_lip_offset_bevel_side") * 1e3,
              res(m, "needle_energy_balance_error"));
  EXPECT_GT(res(m, "cracked_length"), 4e-3);
  EXPECT_LT(res(m, "path_lip_offset_wall_side_max"), 0.0);
  EXPECT_GT(res(m, "path_lip_offset_bevel_side_min"), 0.0);
  EXPECT_LT(res(m, "needle_energy_balance_error"), 0.02);
}

// Bad path inputs: each names the file, line, field, value and what is allowed.
TEST(PathNeedle, BadPathInputsAreRejected) {
  struct Case {
    std::string path, extra, field, words;
  };
  const std::vector<Case> cases = {
      {"      path: points\n      path_points: [{x: 0 mm, y: 0 mm}, {x: 3 mm, y: 0.1 mm}, {x: 2 mm, y: 0.2 mm}]\n", "",
       "path_points[2].x", "does not increase"},
      {"      path: points\n      path_points: [{x: 0.5 mm, y: 0 mm}, {x: 3 mm, y: 0 mm}]\n", "", "path_points[0].x",
       "entry point"},
      {"      path: points\n      path_points: [{x: 0 mm, y: 0 mm}, {x: 2 mm, y: 2.5 mm}]\n", "", "path_points[1].y",
       "45 deg"},
      {"      path: points\n      path_points: [{x: 0 mm, y: 0 mm}, {x: 12 mm, y: 0 mm}]\n", "", "path_points[1].x",
       "outside the tissue block"},
      {"      path: points\n      path_points: [{x: 0 mm, y: 0 mm}]\n", "", "cohesive.path", "at least 2"},
      {"      path: arc\n      path_radius: 5 mm\n", "", "cohesive.path", "4 needle diameters"},
      {"      path: arc\n      path_radius: 30 mm\n", "3d", "cohesive.path", "2d only"},
      {"      path: arc\n      path_radius: 30 mm\n", "    needle_model: beam\n", "cohesive.path", "rigid"},
      {"      path_points: [{x: 0 mm, y: 0 mm}, {x: 3 mm, y: 0 mm}]\n", "", "path_points", "path is straight"},
      {"      path: wiggly\n", "", "cohesive.path", "straight, points, arc, steering"},
  };
  for (const auto& c : cases) {
    std::string t = yaml(c.path, 3e-3, 0.3, c.extra == "3d" ? "" : c.extra);
    if (c.extra == "3d") {
      t.replace(t.find("    element: quad4\n"), 19, "");
      t.replace(t.find("dimension: 2d"), 13, "dimension: 3d");
    }
    try {
      scenario::readText(t, "bad.yaml");
      ADD_FAILURE() << "accepted: " << c.path;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find("bad.yaml:"), std::string::npos) << msg;
      EXPECT_NE(msg.find(c.field), std::string::npos) << msg;
      EXPECT_NE(msg.find(c.words), std::string::npos) << msg;
      EXPECT_NE(msg.find("allowed"), std::string::npos) << msg;
    }
  }
}

// path_file: the same points from a CSV next to the scenario (units in the header); a bad row names the CSV
// file and its line.
TEST(PathNeedle, PathFromCsvFile) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "needlesim_path_file_test";
  fs::create_directories(dir);
  std::ofstream(dir / "path.csv") << "# an arc of 30 mm\nx [mm],y [um]\n0,0\n2,66.7\n4,267.9\n6,606.1\n";
  std::ofstream(dir / "bad.csv") << "x [mm],y [mm]\n0,0\n2,0.1\n1.5,0.2\n";
  const std::string good = yaml("      path: points\n      path_file: path.csv\n", 3e-3);
  std::ofstream(dir / "good.yaml") << good;
  const Scenario sc = scenario::readFile(dir / "good.yaml");
  const auto& pp = sc.model.explicit_fe.cohesive.path_points;
  ASSERT_EQ(pp.size(), 4u);
  EXPECT_NEAR(pp[3].x, 6e-3, 1e-15);
  EXPECT_NEAR(pp[3].y, 606.1e-6, 1e-15);
  std::ofstream(dir / "bad.yaml") << yaml("      path: points\n      path_file: bad.csv\n", 3e-3);
  try {
    scenario::readFile(dir / "bad.yaml");
    ADD_FAILURE() << "bad.csv accepted";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("bad.csv:4"), std::string::npos) << msg;
    EXPECT_NE(msg.find("does not increase"), std::string::npos) << msg;
  }
  std::ofstream(dir / "missing.yaml") << yaml("      path: points\n      path_file: nowhere.csv\n", 3e-3);
  EXPECT_THROW(scenario::readFile(dir / "missing.yaml"), InputError);
  fs::remove_all(dir);
}
