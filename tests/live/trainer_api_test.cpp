// The trainer's anatomy in its API (GET /api/info, GET /api/frame; docs/serve.md): the tissue's
// outline, the inclusions with the vertices of their material, their displaced centres and the
// target's miss distance from the tip, for realtime3d and realtime2d.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <string>
#include <thread>

#include "needlesim/live/live_session.hpp"
#include "needlesim/live/web_server.hpp"

namespace live = needlesim::live;
namespace api = needlesim::api;
namespace fs = std::filesystem;

namespace {

api::Scenario example(const std::string& path) { return api::Scenario::fromFile(fs::path(NEEDLESIM_SOURCE_DIR) / "examples" / path); }

live::LiveSettings quickSettings() {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  return settings;
}

double distance(const std::vector<double>& a, const std::vector<double>& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

// Holds the needle where it is and runs the session until the viewer thread has published a
// field of the steps taken so far.
void viewLatest(live::LiveSession& session) {
  const std::uint64_t taken = session.latest().step;
  session.setDrive({});
  session.start();
  live::Frame f;
  for (int wait = 0; wait < 1000 && (f.fields == 0 || f.fieldStep < taken); ++wait) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    session.frame(f);
  }
  session.stop();
}

}  // namespace

// examples/realtime3d/tumour_target.yaml: a 6 mm tumour 25 mm deep, 2 mm to +y, in a
// 40 mm block of 11 x 9 x 9 nodes.
TEST(LiveWeb, InfoGivesTheBlocksOutlineAndTheTumourWithItsRegion) {
  live::LiveSession session(example("realtime3d/tumour_target.yaml"), quickSettings());
  const nlohmann::json info = live::infoJson(session, live::WebInfo{"tumour", "", -1});
  EXPECT_EQ(info["outline"]["kind"], "block");
  EXPECT_TRUE(info["outline"]["file"].is_null());
  const std::vector<double> lo = info["outline"]["lo"], hi = info["outline"]["hi"];
  EXPECT_LT(distance(lo, {0.0, -0.02, -0.02}), 1e-9);  // tissue frame: x from the entry face, y and z centred
  EXPECT_LT(distance(hi, {0.04, 0.02, 0.02}), 1e-9);

  ASSERT_EQ(info["inclusions"].size(), 1u);
  const nlohmann::json& tumour = info["inclusions"][0];
  EXPECT_EQ(tumour["name"], "tumour");
  EXPECT_EQ(tumour["shape"], "sphere");
  EXPECT_EQ(tumour["target"], true);
  EXPECT_NEAR(tumour["radius"].get<double>(), 0.006, 1e-12);
  const std::vector<double> centre = tumour["centre"];
  EXPECT_LT(distance(centre, {0.025, 0.002, 0.0}), 1e-12);
  // Its region: the nodes of the elements whose centre is in the sphere, so each within the
  // radius and one element diagonal (4 x 5 x 5 mm spacing: 8.1 mm) of the centre.
  const std::vector<double>& v = session.surface().vertices;
  const std::vector<int> region = tumour["region"];
  ASSERT_GT(region.size(), 4u);
  for (const int n : region) {
    const std::size_t k = 3 * static_cast<std::size_t>(n);
    ASSERT_LT(k + 2, v.size());
    EXPECT_LT(distance({v[k], v[k + 1], v[k + 2]}, centre), 0.006 + 0.0082) << n;
  }
}

// Before the viewer's first field there is no miss. At the first step the tip is at the entry
// point (the trainer starts at depth 0) on the x axis and the tumour has not moved: the miss is
// the distance to its centre, 2 mm off the axis. Inserted 12 mm, the tip is 12 mm nearer; the
// tumour, pushed by the tissue ahead of the tip, moves along +x.
TEST(LiveWeb, FrameGivesTheTumoursMissDistanceFromTheTip) {
  live::LiveSession session(example("realtime3d/tumour_target.yaml"), quickSettings());
  EXPECT_TRUE(live::frameJson(session, 0)["inclusions"][0]["miss"].is_null());
  session.advance(1);
  viewLatest(session);
  const nlohmann::json before = live::frameJson(session, 0)["inclusions"];
  ASSERT_EQ(before.size(), 1u);
  EXPECT_NEAR(before[0]["miss"].get<double>(), std::hypot(0.025, 0.002), 1e-7);
  EXPECT_NEAR(before[0]["missFromAxis"].get<double>(), 0.002, 1e-7);

  session.setDrive({1.0});
  session.advance(600);  // 12 mm at 20 mm/s
  viewLatest(session);
  const nlohmann::json frame = live::frameJson(session, 0);
  const nlohmann::json& tumour = frame["inclusions"][0];
  const std::vector<double> needle = frame["needle"], moved = tumour["centre"];
  const std::vector<double> tip(needle.end() - 3, needle.end());
  EXPECT_GT(tip[0], 0.011);
  EXPECT_GT(moved[0], 0.025);  // pushed ahead
  EXPECT_LT(distance(moved, {0.025, 0.002, 0.0}), 1e-3);
  EXPECT_NEAR(tumour["miss"].get<double>(), distance(moved, tip), 1e-6);  // the JSON's floats
  EXPECT_LT(tumour["miss"].get<double>(), std::hypot(0.026, 0.002) - 0.011);
  EXPECT_GT(tumour["missFromAxis"].get<double>(), 0.0);
  EXPECT_LT(tumour["missFromAxis"].get<double>(), tumour["miss"].get<double>());
}

// realtime2d: the layered example's target, a 3 mm vessel (cylinder) 40 mm deep and 3 mm to +y;
// the imported example's outline is its geometry file, its tumour a group of that mesh.
TEST(LiveWeb, Realtime2dGivesTheTargetAndAnImportedOutline) {
  live::LiveSession layered(example("realtime2d/layered_target.yaml"), quickSettings());
  const nlohmann::json info = live::infoJson(layered, live::WebInfo{});
  EXPECT_EQ(info["outline"]["kind"], "block");
  ASSERT_EQ(info["inclusions"].size(), 1u);
  EXPECT_EQ(info["inclusions"][0]["shape"], "cylinder");
  EXPECT_FALSE(info["inclusions"][0]["region"].empty());
  layered.advance(1);
  viewLatest(layered);
  const nlohmann::json readout = live::frameJson(layered, 0)["inclusions"][0];
  EXPECT_NEAR(readout["miss"].get<double>(), std::hypot(0.040, 0.003), 1e-7);

  live::LiveSession imported(example("realtime2d/imported_block.yaml"), quickSettings());
  const nlohmann::json outline = live::infoJson(imported, live::WebInfo{})["outline"];
  EXPECT_EQ(outline["kind"], "imported");
  EXPECT_NE(outline["file"].get<std::string>().find("imported_block.geo"), std::string::npos);
  const nlohmann::json tumour = live::infoJson(imported, live::WebInfo{})["inclusions"][0];
  EXPECT_EQ(tumour["shape"], "mesh");
  EXPECT_FALSE(tumour["region"].empty());
  imported.advance(1);
  viewLatest(imported);
  EXPECT_TRUE(live::frameJson(imported, 0)["inclusions"][0]["miss"].is_number());
}
