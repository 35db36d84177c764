// The shared results vocabulary: forces.csv's common columns and order, the
// inclusion motion table and its targeting results in the needle frame.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "needlesim/core/error.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/results/forces_table.hpp"
#include "needlesim/results/inclusion_motion.hpp"

using namespace needlesim;

TEST(ForcesTable, CommonColumnsComeFirstThenTheEngines) {
  results::ForcesTable t(true, {{"force_tip", "N"}});
  results::NeedleForces f;
  f.time = 1.0;
  f.depth = 2.0;
  f.velocity = 3.0;
  f.force_total = 4.0;
  f.force_lateral = -5.0;
  f.tip_x = 6.0;
  f.tip_y = 7.0;
  f.tip_z = 8.0;
  f.tip_deflection = 9.0;
  t.add(f, {10.0});
  const auto& tab = t.table();
  ASSERT_EQ(tab.columns().size(), 10u);
  const char* names[] = {"time", "depth", "velocity", "force_total", "force_lateral", "tip_x", "tip_y", "tip_z",
                         "tip_deflection", "force_tip"};
  for (std::size_t i = 0; i < 10; ++i) {
    EXPECT_EQ(tab.columns()[i].name, names[i]);
    EXPECT_DOUBLE_EQ(tab.at(0, i), static_cast<double>(i + 1) * (i == 4 ? -1.0 : 1.0));
  }
  EXPECT_THROW(t.add(f, {}), Error);  // an engine value missing
  EXPECT_EQ(results::ForcesTable(false).table().columns().size(), 8u);  // rigid: no tip_deflection
  EXPECT_THROW(results::ForcesTable(false, {{"depth", "m"}}), Error);  // a common name reused
}

TEST(InclusionMotion, ReportsTheTargetShiftAlongTheNeedleFrame) {
  InsertionSpec ins;
  ins.entry_angle = 60.0 * std::numbers::pi / 180.0;
  const auto frame = needle::InsertionFrame::fromInsertion(ins);
  InclusionSpec tumour;
  tumour.name = "tumour";
  tumour.target = true;
  InclusionSpec vessel;
  vessel.name = "vessel";
  results::InclusionMotion m({tumour, vessel}, frame);
  const Eigen::Vector3d u = 1e-3 * frame.axial - 2e-3 * frame.lateral + 0.5e-3 * frame.outOfPlane;
  m.add(0.0, 0.0, {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()});
  m.add(1.0, 0.01, {u, Eigen::Vector3d(0, 1e-4, 0)});
  MemorySink sink;
  m.report(sink);
  ASSERT_EQ(sink.tables.count("inclusions"), 1u);
  EXPECT_NEAR(sink.tables["inclusions"].column("tumour_u_lateral").back(), -2e-3, 1e-15);
  auto value = [&](const std::string& k) {
    EXPECT_EQ(sink.results.count(k), 1u) << k;
    return sink.results.count(k) ? sink.results[k].value : 0.0;
  };
  EXPECT_NEAR(value("tumour_shift_lateral"), -2e-3, 1e-15);
  EXPECT_NEAR(value("tumour_shift_axial"), 1e-3, 1e-15);
  EXPECT_NEAR(value("tumour_shift_out_of_plane"), 0.5e-3, 1e-15);
  EXPECT_NEAR(value("tumour_displacement"), u.norm(), 1e-15);
  EXPECT_NEAR(value("vessel_displacement_max"), 1e-4, 1e-15);
  EXPECT_EQ(sink.results.count("vessel_shift_lateral"), 0u);  // not a target
}

TEST(InclusionMotion, TheMissDistanceIsFromTheTipToTheDisplacedTargetCentre) {
  const auto frame = needle::InsertionFrame::fromInsertion(InsertionSpec{});
  InclusionSpec tumour;
  tumour.name = "tumour";
  tumour.target = true;
  tumour.x = 10e-3, tumour.y = 2e-3, tumour.z = 0.0;
  results::InclusionMotion m({tumour}, frame);
  m.add(1.0, 12e-3, {Eigen::Vector3d(0.1e-3, 0.2e-3, -0.3e-3)});
  MemorySink before;
  m.report(before);
  EXPECT_EQ(before.results.count("tumour_miss_distance"), 0u);  // no tip given: no miss
  m.tip(Eigen::Vector3d(12e-3, 0, 0), Eigen::Vector3d(2, 0, 0));
  MemorySink sink;
  m.report(sink);
  // centre now (10.1, 2.2, -0.3) mm; tip (12, 0, 0) mm on an axis along x
  EXPECT_NEAR(sink.results.at("tumour_miss_distance").value, 1e-3 * std::sqrt(1.9 * 1.9 + 2.2 * 2.2 + 0.3 * 0.3), 1e-15);
  EXPECT_NEAR(sink.results.at("tumour_miss_from_axis").value, 1e-3 * std::sqrt(2.2 * 2.2 + 0.3 * 0.3), 1e-15);
}
