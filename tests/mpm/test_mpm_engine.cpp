// The mpm engine end to end: scenarios read through the scenario reader and run
// into an in-memory sink (seed 000 sections 3-4; docs/validation/mpm.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/mpm/marker_errors.hpp"
#include "needlesim/engines/mpm/mpm_engine.hpp"
#include "needlesim/io/csv_reader.hpp"
#include "needlesim/scenario/measured_data.hpp"
#include "needlesim/scenario/reader.hpp"
#include "mpm_test_scenario.hpp"

using namespace needlesim;
using namespace needlesim::mpm_test;


// No force while the needle is outside the block; the blunt face meets the
// material at depth 0 (the entry face) and the force then rises with depth.
TEST(MpmEngine, ZeroForceBeforeContactThenRising) {
  const MemorySink out = runText(smallScenario());
  const io::Table& f = out.tables.at("forces");
  const auto depth = f.column("depth"), force = f.column("force_total"), tip = f.column("force_tip"),
             shaft = f.column("force_shaft");
  ASSERT_GT(f.rows(), 50u);
  double firstContact = NAN, atOne = NAN, atTwo = NAN;
  for (std::size_t i = 0; i < f.rows(); ++i) {
    EXPECT_TRUE(std::isfinite(force[i]));
    EXPECT_NEAR(tip[i] + shaft[i], force[i], 1e-9 * (1 + std::abs(force[i])));
    if (depth[i] < -0.05e-3) EXPECT_EQ(force[i], 0.0) << "force before contact at depth " << depth[i];
    if (std::isnan(firstContact) && force[i] > 0) firstContact = depth[i];
    if (std::isnan(atOne) && depth[i] >= 1e-3) atOne = force[i];
    if (std::isnan(atTwo) && depth[i] >= 2e-3) atTwo = force[i];
  }
  // Contact within a step of the surface: the needle moves 6 mm/s x 10 ms per row.
  EXPECT_NEAR(firstContact, 0.0, 0.1e-3);
  EXPECT_GT(atOne, 0.0);
  EXPECT_GT(atTwo, atOne);
  EXPECT_GT(out.results.at("final_force").value, atTwo);
  EXPECT_NEAR(out.results.at("final_depth").value, 3e-3, 1e-9);
  EXPECT_EQ(out.results.at("particles").value, 768.0);
  EXPECT_TRUE(out.tables.count("energy"));
}

// The KE / IE plot draws the ratio only where the internal energy is at least 1 % of its
// largest value (the spike of a near-zero internal energy at first contact is left out, as
// in max_ke_ie); a second plot shows both energies over the whole run.
TEST(MpmEngine, EnergyRatioPlotLeavesOutTheStretchOfNegligibleInternalEnergy) {
  const MemorySink out = runText(smallScenario());
  const io::Table& e = out.tables.at("energy");
  const auto ie = e.column("internal");
  const double ieMax = *std::max_element(ie.begin(), ie.end());
  const io::Plot* ratio = nullptr;
  const io::Plot* energies = nullptr;
  for (const auto& p : out.plots) {
    if (p.ylabel == "KE / IE [-]") ratio = &p;
    if (p.ylabel == "energy [J]") energies = &p;
  }
  ASSERT_NE(ratio, nullptr);
  ASSERT_NE(energies, nullptr);
  ASSERT_EQ(energies->series.size(), 2u);
  EXPECT_EQ(energies->series[1].y, ie);
  const auto& y = ratio->series.at(0).y;
  ASSERT_EQ(y.size(), ie.size());
  std::size_t left = 0, drawn = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const bool meaningful = ie[i] >= 0.01 * ieMax;
    EXPECT_EQ(std::isfinite(y[i]), meaningful) << "row " << i << ", internal energy " << ie[i];
    if (meaningful) EXPECT_LE(y[i], out.results.at("max_ke_ie").value);
    (meaningful ? drawn : left) += 1;
  }
  EXPECT_GT(left, 0u);  // before contact
  EXPECT_GT(drawn, 0u);
}

// Seed 000 eq 35: a measured curve that is the simulated one plus 0.1 N gives
// RMSE = MAE = 0.1 N (depth interpolation inside the simulated range).
TEST(MpmEngine, RmseAndMaeAgainstMeasuredCurve) {
  const MemorySink ref = runText(smallScenario());
  const io::Table& f = ref.tables.at("forces");
  const auto depth = f.column("depth"), force = f.column("force_total");
  const auto csv = std::filesystem::temp_directory_path() / "needlesim_mpm_measured_force.csv";
  {
    std::ofstream o(csv);
    o << "depth [mm],force [N]\n";
    for (std::size_t i = 0; i < f.rows(); i += 7) o << depth[i] * 1e3 << "," << force[i] + 0.1 << "\n";
    o << "99,1\n";  // outside the simulated depths: ignored
  }
  const MemorySink out = runText(smallScenario("    measured_force: " + csv.string() + "\n"));
  std::filesystem::remove(csv);
  EXPECT_NEAR(out.results.at("rmse_force").value, 0.1, 1e-6);
  EXPECT_NEAR(out.results.at("mae_force").value, 0.1, 1e-6);
  EXPECT_EQ(out.results.at("measured_points").value, static_cast<double>((f.rows() + 6) / 7));
}

// Markers follow material points: one just beside the needle path is pushed
// away from it (sideways) and forward; one near the fixed exit face hardly moves.
TEST(MpmEngine, MarkersMoveWithTheTissue) {
  const MemorySink out = runText(smallScenario(
      "    marker_depth_step: 1 mm\n"
      "    markers:\n"
      "      - {name: near, x: 1.25 mm, y: 0.75 mm}\n"
      "      - {name: far, x: 5.75 mm, y: 1.75 mm}\n",
      "conical"));
  const io::Table& m = out.tables.at("markers");
  EXPECT_GE(m.rows(), 4u);  // depth 0 (start row -0.5 mm), 1, 2, 3 mm
  EXPECT_GT(m.column("near_uy").back(), 0.02e-3);  // pushed away from the path (+y side)
  EXPECT_GT(m.column("near_ux").back(), 0.0);      // dragged forward
  EXPECT_LT(out.results.at("marker_far_uxy_final").value, 0.25 * out.results.at("marker_near_uxy_final").value);
}

// Seed 000 eq 37 against measured markers: the engine's own marker history as
// the "measurement" gives zero error; shifting every measured ux by 0.05 mm
// gives r_max,x = r_mean,x = 0.05 mm at every depth, and r_max (on u_xy, eq 36)
// at most the shift (triangle inequality).
TEST(MpmEngine, MarkerErrorsAgainstMeasuredMarkers) {
  const std::string mk =
      "    marker_depth_step: 1 mm\n"
      "    markers:\n"
      "      - {name: near, x: 1.25 mm, y: 0.75 mm}\n"
      "      - {name: Far, x: 4.25 mm, y: -1.25 mm}\n";
  const MemorySink ref = runText(smallScenario(mk, "conical"));
  const io::Table& m = ref.tables.at("markers");
  ASSERT_GE(m.rows(), 4u);
  EXPECT_GT(m.column("near_uy").back(), 0.02e-3);  // the comparison is not between zeros
  const auto csv = std::filesystem::temp_directory_path() / "needlesim_mpm_measured_markers.csv";
  auto write = [&](double shift) {
    std::ofstream o(csv);
    o.precision(17);
    o << "depth [mm],near_ux [mm],near_uy [mm],far_ux [mm],far_uy [mm]\n";
    for (std::size_t i = 1; i < m.rows(); ++i)
      o << m.column("depth")[i] * 1e3 << "," << (m.column("near_ux")[i] + shift) * 1e3 << ","
        << m.column("near_uy")[i] * 1e3 << "," << (m.column("Far_ux")[i] + shift) * 1e3 << ","
        << m.column("Far_uy")[i] * 1e3 << "\n";
    o << "99,0,0,0,0\n";  // outside the simulated depths: ignored
  };
  write(0.0);
  const MemorySink exact = runText(smallScenario(mk + "    measured_markers: " + csv.string() + "\n", "conical"));
  EXPECT_EQ(exact.results.at("marker_measured_depths").value, static_cast<double>(m.rows() - 1));
  EXPECT_LT(exact.results.at("marker_r_max").value, 1e-12);
  EXPECT_LT(exact.results.at("marker_r_mean").value, 1e-12);
  const double s = 0.05e-3;
  write(s);
  const MemorySink shifted = runText(smallScenario(mk + "    measured_markers: " + csv.string() + "\n", "conical"));
  std::filesystem::remove(csv);
  const io::Table& e = shifted.tables.at("marker_errors");
  ASSERT_EQ(e.rows(), m.rows() - 1);
  for (std::size_t i = 0; i < e.rows(); ++i) {
    EXPECT_NEAR(e.column("r_max_x")[i], s, 1e-12);
    EXPECT_NEAR(e.column("r_mean_x")[i], s, 1e-12);
    EXPECT_LT(e.column("r_max_y")[i], 1e-12);
    EXPECT_LE(e.column("r_max")[i], s + 1e-12);
    EXPECT_LE(e.column("r_mean")[i], e.column("r_max")[i] + 1e-15);
  }
  EXPECT_GT(shifted.results.at("marker_r_max").value, 0.5 * s);
}

// Interpolation in depth and eq 36 on a track with uy = 0: the u_xy error is the shift.
TEST(MpmEngine, MarkerErrorsInterpolateInDepth) {
  const std::vector<double> depth{0.0, 1e-3, 2e-3, 3e-3};
  const std::vector<mpm::MarkerTrack> sim{{"a", {0.0, 0.1e-3, 0.2e-3, 0.3e-3}, {0, 0, 0, 0}}};
  const std::vector<MpmMarkerSpec> markers{{"a", 0, 0, 0}};
  const auto measured = [&](const char* text) { return scenario::measuredMarkersFrom(io::parseCsv(text, "m.csv"), markers); };
  const auto rows = mpm::compareMarkers(measured("depth [mm],A_ux [um],a_uy [mm]\n1.5,170,0\n2.5,250,0\n"), depth, sim);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_NEAR(rows[0].rmax, 0.02e-3, 1e-15);  // simulated 0.15 mm at 1.5 mm
  EXPECT_NEAR(rows[1].rmean, 0.0, 1e-15);
  // A marker with only one of its columns, or none of the simulated markers.
  EXPECT_THROW(measured("depth [mm],a_ux [mm]\n1,0\n"), InputError);
  EXPECT_THROW(measured("depth [mm],b_ux [mm],b_uy [mm]\n1,0,0\n"), InputError);
}

// model.mpm.anti_locking: fbar reaches the solver (named in the run note) and,
// for this compressible block (nu 0.45), changes the force little.
TEST(MpmEngine, FbarOptionReachesTheSolver) {
  const MemorySink plain = runText(smallScenario());
  const MemorySink fbar = runText(smallScenario("    anti_locking: fbar\n"));
  bool named = false;
  for (const auto& n : fbar.notes) named = named || n.find("with F-bar") != std::string::npos;
  EXPECT_TRUE(named);
  const double f0 = plain.tables.at("forces").column("force_total").back();
  const double f1 = fbar.tables.at("forces").column("force_total").back();
  EXPECT_GT(f1, 0.0);
  EXPECT_NEAR(f1 / f0, 1.0, 0.25);
  EXPECT_NE(f1, f0);
}

TEST(MpmEngine, ScenarioErrors) {
  // Points coarser than the grid leave empty cells.
  EXPECT_THROW(scenario::readText(replaced(smallScenario(), "particle_spacing: 0.5 mm", "particle_spacing: 1.5 mm"), "t.yaml"), InputError);
  // A measured curve that does not exist is refused by `needlesim check` already.
  EXPECT_THROW(scenario::readText(smallScenario("    measured_force: /nonexistent/f.csv\n"), "t.yaml"), InputError);
  EXPECT_THROW(scenario::readText(replaced(smallScenario(), "exit: fixed", "entry: sticky"), "t.yaml"), InputError);
  // Measured markers without markers to compare.
  const auto csv = std::filesystem::temp_directory_path() / "needlesim_mpm_markers_only.csv";
  { std::ofstream(csv) << "depth [mm],a_ux [mm],a_uy [mm]\n1,0,0\n"; }
  EXPECT_THROW(scenario::readText(smallScenario("    measured_markers: " + csv.string() + "\n"), "t.yaml"), InputError);
  std::filesystem::remove(csv);
}

// An empty measured-markers file (or one with a header and no rows) is refused
// when the scenario is read, i.e. by `needlesim check`, naming the file.
TEST(MpmEngine, CheckRefusesEmptyMeasuredMarkers) {
  const std::string mk = "    markers:\n      - {name: near, x: 1.25 mm, y: 0.75 mm}\n";
  const auto csv = std::filesystem::temp_directory_path() / "needlesim_mpm_markers_empty.csv";
  const std::string yaml = smallScenario(mk + "    measured_markers: " + csv.string() + "\n");
  for (const char* text : {"", "depth [mm],near_ux [mm],near_uy [mm]\n"}) {
    { std::ofstream(csv) << text; }
    try {
      scenario::readText(yaml, "t.yaml");
      ADD_FAILURE() << "accepted a measured-markers file holding '" << text << "'";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find(csv.string()), std::string::npos) << what;
      EXPECT_TRUE(what.find("empty") != std::string::npos || what.find("no data rows") != std::string::npos) << what;
    }
  }
  { std::ofstream(csv) << "depth [mm],near_ux [mm],near_uy [mm]\n1,0,0\n"; }
  EXPECT_NO_THROW(scenario::readText(yaml, "t.yaml"));
  std::filesystem::remove(csv);
}

// The quick example of examples/mpm runs and gives a resisting force.
TEST(MpmEngine, QuickExampleRuns) {
  const auto path = std::filesystem::path(NEEDLESIM_SOURCE_DIR) / "examples/mpm/quick_needle_block.yaml";
  const Scenario sc = scenario::readFile(path);
  const MemorySink out = runInMemory(sc, RunOptions{false});
  EXPECT_GT(out.results.at("peak_force").value, 0.0);
  EXPECT_GT(out.results.at("final_shaft_force").value, 0.0);  // friction along the shaft (mu = 0.255)
}

// Seed 000 section 3.4: a 1 mm conical needle (30 deg half-angle) 7 mm into a
// 10 x 5 x 5 mm block (1 mm grid, 0.5 mm points) separates the tissue: the
// points on the path first ride ahead of the tip, then part. Separated pairs
// appear only after contact, never far ahead of the tip and only within about
// a cell of the path. The grid contact (eqs 14-21), which acts on whole nodes: the CFEMP default
// resolves this cone at the points and separates none here.
TEST(MpmEngine, NumericalFractureNearThePathAfterContact) {
  std::string s = replaced(smallScenario("    contact: grid\n", "conical"), "outer_diameter: 1 mm", "outer_diameter: 1 mm\n  bevel_angle: 30 deg");
  s = replaced(s, "length: 6 mm, width: 4 mm, height: 4 mm", "length: 10 mm, width: 5 mm, height: 5 mm");
  s = replaced(s, "to: 3 mm", "to: 7 mm");
  const MemorySink out = runText(s);
  const io::Table& fr = out.tables.at("fracture");
  const double pairs = out.results.at("fracture_pairs").value;
  ASSERT_GT(pairs, 0.0);
  ASSERT_GT(fr.rows(), 0u);
  const double h = 1e-3, R = 0.5e-3;
  const auto tip = fr.column("tip_depth"), path = fr.column("path_depth"), count = fr.column("new_pairs");
  double sum = 0.0;
  for (std::size_t i = 0; i < fr.rows(); ++i) {
    EXPECT_GT(tip[i], 0.0) << "separation before the needle touched the block";
      EXPECT_LT(path[i], tip[i] + 2 * h) << "separation far ahead of the tip";
    EXPECT_GT(path[i], -h) << "separation outside the block";
    sum += count[i];
  }
  EXPECT_EQ(sum, pairs);
  EXPECT_EQ(fr.column("total_pairs").back(), pairs);
  EXPECT_LT(out.results.at("fracture_max_offset").value, R + h);
  EXPECT_GT(out.results.at("fracture_onset_depth").value, 0.0);
  EXPECT_LT(out.results.at("fracture_onset_depth").value, 7e-3);
  EXPECT_GT(out.results.at("fracture_deepest").value, 0.0);
  EXPECT_LE(out.results.at("fracture_deepest").value, 7e-3 + 2 * h);
  std::printf("fracture: %g pairs, onset at tip depth %.3f mm, deepest %.3f mm, max offset %.3f mm\n", pairs,
              out.results.at("fracture_onset_depth").value * 1e3, out.results.at("fracture_deepest").value * 1e3,
              out.results.at("fracture_max_offset").value * 1e3);
  // The shallower (3 mm), sharper (20 deg) insertion of the other tests parts fewer pairs.
  const MemorySink thin = runText(smallScenario("", "conical"));
  EXPECT_LT(thin.results.at("fracture_pairs").value, pairs);
}

// CFEMP contact (eqs 22-24) through the engine: no force before the needle
// reaches the block, then a force that rises with depth.
TEST(MpmEngine, CfempZeroForceBeforeContactThenRising) {
  const MemorySink out = runText(smallScenario("    contact: cfemp\n", "conical"));
  const io::Table& f = out.tables.at("forces");
  const auto depth = f.column("depth"), force = f.column("force_total");
  double firstContact = NAN, atOne = NAN, atTwo = NAN;
  for (std::size_t i = 0; i < f.rows(); ++i) {
    ASSERT_TRUE(std::isfinite(force[i]));
    if (depth[i] < 0.0) EXPECT_EQ(force[i], 0.0) << "force before contact at depth " << depth[i];
    if (std::isnan(firstContact) && force[i] > 0) firstContact = depth[i];
    if (std::isnan(atOne) && depth[i] >= 1e-3) atOne = force[i];
    if (std::isnan(atTwo) && depth[i] >= 2e-3) atTwo = force[i];
  }
  std::printf("cfemp: first contact at %.3f mm, F(1 mm) %.4g N, F(2 mm) %.4g N, F(3 mm) %.4g N\n",
              firstContact * 1e3, atOne, atTwo, out.results.at("final_force").value);
  // The sharp cone (half-angle 20 deg) enters between the four points nearest
  // the axis (0.35 mm off it, 0.25 mm deep): its wall comes within d_p/2 of them
  // (eq 22, d_e = 0) about 0.5 mm deep.
  EXPECT_GE(firstContact, 0.0);
  EXPECT_LT(firstContact, 0.8e-3);
  EXPECT_GT(atOne, 0.0);
  EXPECT_GT(atTwo, atOne);
  EXPECT_GT(out.results.at("final_force").value, atTwo);
}

namespace {
// High-frequency content of a force curve: RMS of the force minus its centred
// moving average (window rows), over the rows with depth in [d0, d1], relative
// to the mean force there.
double forceNoise(const MemorySink& out, int window, double d0, double d1, double* mean = nullptr) {
  const io::Table& f = out.tables.at("forces");
  const auto depth = f.column("depth"), force = f.column("force_total");
  const int n = static_cast<int>(f.rows()), w = window / 2;
  double s2 = 0.0, s1 = 0.0;
  int k = 0;
  for (int i = w; i + w < n; ++i) {
    if (depth[static_cast<std::size_t>(i)] < d0 || depth[static_cast<std::size_t>(i)] > d1) continue;
    double avg = 0.0;
    for (int j = i - w; j <= i + w; ++j) avg += force[static_cast<std::size_t>(j)];
    avg /= 2 * w + 1;
    const double r = force[static_cast<std::size_t>(i)] - avg;
    s2 += r * r;
    s1 += force[static_cast<std::size_t>(i)];
    ++k;
  }
  if (mean) *mean = s1 / k;
  return std::sqrt(s2 / k);
}
}  // namespace

// Seed 000 section 5.2: the paper attributes its main error to the cross-grid
// noise of linear shape functions. The same 3 mm insertion with linear and
// quadratic B-spline shapes, the force of every step, high-frequency content
// = RMS of the force minus its centred moving average. Measured here (numbers
// in docs/validation/mpm.md) the B-spline force is NOT quieter with grid
// contact (4.9 % vs 7.3 % of the mean force, 5-step window) and about equal
// with CFEMP, so the paper's claim is not asserted; the test bounds both (a
// regression guard) and prints them.
TEST(MpmEngine, ForceNoiseLinearVsBSpline) {
  for (const char* contact : {"grid", "cfemp"}) {
    std::string base = replaced(smallScenario("", "conical"), "interval: 10 ms", "interval: 0 s");
    base = replaced(base, "threads: 1\n", std::string("threads: 1\n    contact: ") + contact + "\n");
    const MemorySink lin = runText(replaced(base, "threads: 1\n", "threads: 1\n    shape: linear\n"));
    const MemorySink spl = runText(replaced(base, "threads: 1\n", "threads: 1\n    shape: bspline\n"));
    for (int w : {5, 21}) {
      double ml = 0, ms = 0;
      const double nl = forceNoise(lin, w, 0.5e-3, 2.9e-3, &ml), ns = forceNoise(spl, w, 0.5e-3, 2.9e-3, &ms);
      std::printf("%s, window %d steps: linear RMS %.3g N (%.2f %% of mean %.3g N), B-spline RMS %.3g N (%.2f %% of %.3g N)\n",
                  contact, w, nl, 100 * nl / ml, ml, ns, 100 * ns / ms, ms);
      EXPECT_GT(nl, 0.0);
      EXPECT_GT(ns, 0.0);
      EXPECT_LT(nl / ml, 0.12);
      EXPECT_LT(ns / ms, 0.12);
    }
  }
}
