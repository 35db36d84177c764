// The live session layer of needlesim serve (src/needlesim/live): pose motion, the haptic
// protocol's packets, the physics thread, the viewer thread's field, recording and replay.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include "needlesim/live/haptic_protocol.hpp"
#include "needlesim/live/haptic_server.hpp"
#include "needlesim/core/error.hpp"
#include "needlesim/live/live_session.hpp"
#include "needlesim/live/net_address.hpp"
#include "needlesim/live/step_log.hpp"
#include "needlesim/live/web_server.hpp"

namespace live = needlesim::live;
namespace haptic = needlesim::live::haptic;
namespace api = needlesim::api;
namespace fs = std::filesystem;

namespace {
api::Scenario realtime2d() {
  return api::Scenario::fromFile(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/realtime2d/thesis_gelatin_18G_3mms.yaml")
      .with({{"model.realtime2d.nodes_depth", "11"}, {"model.realtime2d.nodes_lateral", "15"}});
}
}  // namespace

TEST(LivePose, DriveMovesTheTargetWithinLimitsAndPoseFollowsAtTopSpeed) {
  live::MotionLimits limits;
  const live::Controls controls{true, true, false, true};  // realtime2d: lateral, rotation, roll
  live::Pose target;
  for (int i = 0; i < 1000; ++i) live::driveTarget(target, {1.0, 0, 0.5, 1.0, 0}, limits, controls, 1e-3);
  EXPECT_NEAR(target.depth, 5e-3, 1e-12);                 // 1 s at 5 mm/s
  EXPECT_NEAR(target.rotation, 0.25, 1e-12);              // half of 0.5 rad/s
  EXPECT_EQ(target.tilt, 0.0);                            // realtime2d takes no tilt
  live::Pose pose;
  live::approach(pose, {0.01, 0, 0, 0, 0}, limits, 1e-3);
  EXPECT_NEAR(pose.depth, 5e-6, 1e-15);                   // one step at the top speed
  const live::Pose clamped = live::clampTarget({1.0, 1.0, 1.0, 1.0, 1.0}, limits, live::Controls{});
  EXPECT_EQ(clamped.depth, limits.maxDepth);
  EXPECT_EQ(clamped.lateral + clamped.rotation + clamped.tilt + clamped.roll, 0.0);  // lumped: depth only
}

TEST(HapticProtocol, PacketsRoundTripLittleEndianAtTheirSizes) {
  const haptic::PosePacket pose{7, 1, 123456789, {0.01, 1e-3, 0.1, 0.2, 3.0}};
  const haptic::Bytes b = haptic::encode(pose);
  ASSERT_EQ(b.size(), haptic::kPoseSize);
  EXPECT_EQ(b[0], 'N');
  EXPECT_EQ(b[3], 'P');
  EXPECT_EQ(b[4], 1);  // version 1, little-endian
  const haptic::Decoded d = haptic::decode(b);
  ASSERT_TRUE(d.packet);
  const auto& back = std::get<haptic::PosePacket>(*d.packet);
  EXPECT_EQ(back.sequence, 7u);
  EXPECT_EQ(back.clientTimeNs, 123456789u);
  EXPECT_EQ(back.pose.roll, 3.0);
  haptic::StatePacket state;
  state.force = {-0.5, 0.1, 0.0};
  state.phase = 2;
  const haptic::Bytes s = haptic::encode(state);
  ASSERT_EQ(s.size(), haptic::kStateSize);
  EXPECT_EQ(std::get<haptic::StatePacket>(*haptic::decode(s).packet).force[0], -0.5);
  EXPECT_EQ(haptic::encode(haptic::ErrorPacket{1, haptic::ErrorCode::Size, 0, "x"}).size(), haptic::kErrorSize);
}

TEST(HapticProtocol, RefusesOtherVersionsSizesAndNonFinitePoses) {
  haptic::Bytes b = haptic::encode(haptic::PosePacket{3, 0, 0, {}});
  b[4] = 2;
  auto d = haptic::decode(b);
  ASSERT_TRUE(d.error);
  EXPECT_EQ(d.error->code, haptic::ErrorCode::Version);
  EXPECT_EQ(d.error->sequence, 3u);
  const haptic::Decoded back = haptic::decode(haptic::encode(*d.error));
  EXPECT_NE(std::get<haptic::ErrorPacket>(*back.packet).message.find("version 2"), std::string::npos);
  b[4] = 1;
  b.pop_back();
  EXPECT_EQ(haptic::decode(b).error->code, haptic::ErrorCode::Size);
  b = haptic::encode(haptic::PosePacket{3, 0, 0, {NAN, 0, 0, 0, 0}});
  EXPECT_EQ(haptic::decode(b).error->code, haptic::ErrorCode::Value);
  b[0] = 'X';
  const haptic::Decoded other = haptic::decode(b);
  EXPECT_FALSE(other.packet || other.error);  // not this protocol: no answer
}

TEST(LiveSession, PhysicsThreadStepsAtItsRateAndInsertionRaisesTheForce) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  live::LiveSession session(realtime2d(), settings);
  EXPECT_GT(session.settings().limits.maxDepth, 0.05);  // from the tissue and the needle
  session.start();
  session.setDrive({1.0});
  std::this_thread::sleep_for(std::chrono::milliseconds(800));
  session.setDrive({});
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  session.stop();
  const live::LatestState last = session.latest();
  live::Frame frame;
  session.frame(frame);
  std::size_t total = 0;
  session.samples(0, total);
  EXPECT_GT(last.step, 500u);             // ~1100 at 1 kHz; a loaded machine gets fewer
  EXPECT_EQ(session.log().size(), last.step);
  EXPECT_GT(last.state.depth, 5e-3);
  EXPECT_GT(last.state.axial_force, 0.04);
  EXPECT_GT(frame.punctureDepth, 0.0);
  EXPECT_GT(total, 40u);
  EXPECT_EQ(frame.field.scalar.size(), session.surface().vertices.size() / 3);
  std::printf("physics: %llu steps, %.0f steps/s over the last second\n", static_cast<unsigned long long>(last.step), frame.rate);
}

TEST(LiveSession, RecordingReplaysToTheSameForces) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  live::LiveSession session(realtime2d(), settings);
  session.start();
  session.setDrive({1.0, 0.0, 0.3});
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  session.setDrive({-1.0});
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  session.stop();
  const fs::path dir = fs::temp_directory_path() / ("needlesim_live_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  live::writeRecording(session.scenario(), session.log(), dir, false, 1.0, "test");
  ASSERT_TRUE(fs::exists(dir / "commands.csv"));
  api::Scenario again = api::Scenario::builtIn();
  const live::StepLog replayed = live::replay(dir, again);
  EXPECT_EQ(again.engine(), "realtime2d");
  ASSERT_EQ(replayed.size(), session.log().size());
  EXPECT_LT(live::largestDifference(replayed.forcesTable(true), dir / "forces.csv"), 1e-9);
  fs::remove_all(dir);
}

// The 3D engine live: the surface a viewer draws is the block's boundary, a held tilt reaches
// the engine (the tip leaves the insertion plane: tip_z), and the recording replays exactly.
TEST(LiveSession, Realtime3dTakesTheTiltAndReplays) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  const api::Scenario scenario = api::Scenario::fromFile(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/realtime3d/quick_block.yaml");
  live::LiveSession session(scenario, settings);
  EXPECT_TRUE(session.controls().tilt);
  const api::Surface surface = session.surface();
  ASSERT_GT(surface.triangles.size(), 0u);
  for (std::size_t k = 0; k < surface.vertices.size(); k += 3)
    EXPECT_GE(surface.vertices[k], -1e-12);  // the block starts at the entry face, x = 0
  session.start();
  session.setDrive({1.0, 0.0, 0.0, 1.0});  // insert while tilting
  std::this_thread::sleep_for(std::chrono::milliseconds(600));
  session.setDrive({});
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  session.stop();
  const live::LatestState last = session.latest();
  EXPECT_GT(last.pose.tilt, 0.0);
  EXPECT_GT(last.state.depth, 3e-3);
  EXPECT_GT(std::abs(last.state.tip_z), 1e-6);  // tilted out of the insertion plane
  const fs::path dir = fs::temp_directory_path() / ("needlesim_live3d_test_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  live::writeRecording(session.scenario(), session.log(), dir, false, 1.0, "test");
  api::Scenario again = api::Scenario::builtIn();
  const live::StepLog replayed = live::replay(dir, again);
  EXPECT_EQ(again.engine(), "realtime3d");
  EXPECT_LT(live::largestDifference(replayed.forcesTable(true), dir / "forces.csv"), 1e-9);
  fs::remove_all(dir);
}

// The physics thread's work per step only snapshots the viewer's field: physics steps run
// without the viewer thread (advance) compute no field and leave the published one as it was;
// the viewer thread then computes the field of the latest snapshot, which is the field a session
// stepped through the same commands gives at that step (the reduced back-end of a 3D block).
TEST(LiveSession, PhysicsStepsOnlySnapshotTheFieldTheViewerThreadComputesIt) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  const api::Scenario scenario = api::Scenario::fromFile(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/realtime3d/quick_block.yaml")
                                     .with("model.realtime3d.solver", "reduced");
  live::LiveSession session(scenario, settings);
  live::Frame initial;
  session.frame(initial);
  EXPECT_EQ(initial.fields, 0u);
  session.setDrive({1.0});
  session.advance(400);  // 8 mm in at 20 mm/s: 25 field snapshots
  live::Frame physicsOnly;
  session.frame(physicsOnly);
  EXPECT_EQ(physicsOnly.latest.step, 400u);
  EXPECT_GT(physicsOnly.latest.state.depth, 5e-3);
  EXPECT_EQ(physicsOnly.fields, 0u);  // the physics work computed none
  EXPECT_EQ(physicsOnly.fieldStep, 0u);
  EXPECT_EQ(physicsOnly.field.displacement, initial.field.displacement);
  EXPECT_EQ(physicsOnly.needle, initial.needle);

  session.setDrive({});
  session.start();
  live::Frame viewed;
  for (int wait = 0; wait < 500 && viewed.fields == 0; ++wait) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    session.frame(viewed);
  }
  session.stop();
  session.frame(viewed);
  ASSERT_GE(viewed.fields, 1u);
  EXPECT_GE(viewed.fieldStep, 400u);
  EXPECT_EQ(viewed.fieldStep % static_cast<std::uint64_t>(settings.fieldEvery), 0u);
  EXPECT_GT(viewed.fieldCost, 0.0);

  api::Session reference(scenario);  // the recorded commands up to the field's step
  const auto& rows = session.log().rows();
  ASSERT_GE(rows.size(), viewed.fieldStep);
  for (std::size_t k = 0; k < viewed.fieldStep; ++k) reference.step(live::commandFor(rows[k].pose), rows[k].dt);
  api::SurfaceField expected;
  reference.surfaceField(expected);
  ASSERT_EQ(viewed.field.displacement.size(), expected.displacement.size());
  double scale = 0.0, difference = 0.0;
  for (std::size_t i = 0; i < expected.displacement.size(); ++i) {
    scale = std::max(scale, std::abs(expected.displacement[i]));
    difference = std::max(difference, std::abs(viewed.field.displacement[i] - expected.displacement[i]));
  }
  EXPECT_GT(scale, 1e-6);
  EXPECT_LE(difference, 1e-12 * scale);
  const std::vector<double> needle = reference.needleCentreLine();
  ASSERT_EQ(viewed.needle.size(), needle.size());
  for (std::size_t i = 0; i < needle.size(); ++i) EXPECT_NEAR(viewed.needle[i], needle[i], 1e-12);
}

namespace {
fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("needlesim_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

// Drives a session by held keys at the physics rate (advance: no wall clock).
void drive(live::LiveSession& session, double insert, int steps) {
  session.setDrive({insert});
  session.advance(steps);
}
}  // namespace

// A reset is part of the recording: every step before and after it is kept, the step after it
// is marked, and the replay resets there too and reproduces every force.
TEST(LiveRecording, ResetsAreRecordedAndReplayed) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  live::LiveSession session(realtime2d(), settings);
  drive(session, 1.0, 600);  // 12 mm in: punctured
  const double firstPeak = session.latest().state.axial_force;
  session.reset();
  drive(session, 1.0, 150);
  session.reset();
  session.reset();  // two requests before the next step: one reset
  drive(session, -1.0, 50);
  const auto& rows = session.log().rows();
  ASSERT_EQ(rows.size(), 800u);
  EXPECT_TRUE(rows[600].reset && rows[750].reset);
  EXPECT_EQ(std::count_if(rows.begin(), rows.end(), [](const live::StepRecord& r) { return r.reset; }), 2);
  EXPECT_NEAR(rows[600].state.depth, rows[0].state.depth, 1e-12);  // started over
  EXPECT_NEAR(rows[799].time, 0.8, 1e-12);                         // time since the recording started
  const fs::path dir = scratch("live_reset");
  live::writeRecording(session.scenario(), session.log(), dir, false, 1.0, "test");
  const std::string summary = [&] {
    std::ifstream in(dir / "summary.json");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  EXPECT_NE(summary.find("\"resets\""), std::string::npos);
  api::Scenario again = api::Scenario::builtIn();
  const live::StepLog replayed = live::replay(dir, again);
  ASSERT_EQ(replayed.size(), 800u);
  EXPECT_TRUE(replayed.rows()[600].reset && replayed.rows()[750].reset);
  EXPECT_GT(firstPeak, 0.05);
  EXPECT_EQ(replayed.rows()[599].state.axial_force, firstPeak);
  EXPECT_LT(live::largestDifference(replayed.forcesTable(true), dir / "forces.csv"), 1e-9);
  fs::remove_all(dir);
}

// A recorded reset flag that is neither 0 nor 1 names the file, its line and the column.
TEST(LiveRecording, ReplayRefusesABadResetFlagWithItsLine) {
  live::LiveSettings settings;
  settings.record = true;
  live::LiveSession session(realtime2d(), settings);
  drive(session, 1.0, 5);
  const fs::path dir = scratch("live_badreset");
  live::writeRecording(session.scenario(), session.log(), dir, false, 1.0, "test");
  std::ifstream in(dir / "commands.csv");
  std::string text(std::istreambuf_iterator<char>(in), {});
  in.close();
  const std::size_t lineEnd = text.find('\n', text.find('\n', text.find('\n') + 1) + 1);  // end of the 3rd line
  ASSERT_EQ(text[lineEnd - 1], '0');
  text[lineEnd - 1] = '7';
  std::ofstream(dir / "commands.csv") << text;
  api::Scenario again = api::Scenario::builtIn();
  try {
    live::replay(dir, again);
    ADD_FAILURE() << "a reset flag 7 was taken";
  } catch (const needlesim::InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("commands.csv"), std::string::npos) << what;
    EXPECT_NE(what.find(":3"), std::string::npos) << what;
    EXPECT_EQ(e.field(), "reset");
  }
  fs::remove_all(dir);
}

// A command the session refuses (its step guard: here a drive that jumps the tip 20 mm in one
// step) is refused with the message the C++ API and Python give for it; the pose holds where
// the session last took it, the physics thread goes on and the frame reports the refusal.
TEST(LiveSession, ARefusedCommandHoldsThePoseAndIsReported) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 20.0;  // 20 mm in one 1 ms step
  live::LiveSession session(realtime2d(), settings);
  session.advance(1);  // takes the pose at depth 0
  session.setDrive({1.0});
  session.advance(3);
  session.setDrive({});
  session.advance(2);
  live::Frame frame;
  session.frame(frame);
  EXPECT_EQ(frame.refusals, 3u);
  EXPECT_EQ(frame.latest.step, 6u);  // held steps go on
  EXPECT_EQ(frame.latest.pose.depth, 0.0);
  EXPECT_EQ(frame.latest.state.depth, session.latest().state.depth);
  EXPECT_EQ(session.log().size(), 6u);  // a replay steps what was taken

  api::Session direct(realtime2d());
  direct.step(api::Command{}, 1e-3);
  try {
    direct.step(api::Command{0.020}, 1e-3);
    ADD_FAILURE() << "a 20 mm step was taken";
  } catch (const api::InputError& e) {
    EXPECT_EQ(frame.refusal, e.what());
  }
  EXPECT_NE(frame.refusal.find("Session.step(depth): moves the tip 20 mm in one step (from 0 mm)"), std::string::npos)
      << frame.refusal;
  const nlohmann::json json = live::frameJson(session, 0);  // GET /api/frame
  EXPECT_EQ(json["refusals"], 3);
  EXPECT_EQ(json["refusal"], frame.refusal);
}

namespace {
// One pose packet to the haptic server on this machine and its answer.
haptic::Decoded exchange(int port, const haptic::PosePacket& pose) {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(static_cast<std::uint16_t>(port));
  to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  timeval timeout{5, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  const haptic::Bytes out = haptic::encode(pose);
  sendto(fd, out.data(), out.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
  std::array<std::uint8_t, 512> in{};
  const ssize_t n = recv(fd, in.data(), in.size(), 0);
  close(fd);
  return haptic::decode({in.data(), static_cast<std::size_t>(std::max<ssize_t>(n, 0))});
}
}  // namespace

// The haptic bridge answers the pose after one the session refused with error code 5 and the
// session's message; the needle holds, and the next answers are states again.
TEST(HapticServer, APoseTheSessionRefusedIsAnsweredWithItsMessage) {
  live::LiveSettings settings;
  settings.limits.insertSpeed = 1.0;  // a device's pose is followed at 20 m/s: 20 mm in one 1 ms step
  live::LiveSession session(realtime2d(), settings);
  live::HapticServer server(session, "127.0.0.1", 0);
  server.start();
  session.advance(1);
  const haptic::Decoded first = exchange(server.port(), haptic::PosePacket{1, 0, 0, {0.020}});
  ASSERT_TRUE(first.packet);
  EXPECT_TRUE(std::holds_alternative<haptic::StatePacket>(*first.packet));
  session.advance(1);  // refused: the tip would move 20 mm in one step
  const haptic::Decoded refused = exchange(server.port(), haptic::PosePacket{2, 0, 0, {0.0}});
  ASSERT_TRUE(refused.packet);
  ASSERT_TRUE(std::holds_alternative<haptic::ErrorPacket>(*refused.packet));
  const auto& error = std::get<haptic::ErrorPacket>(*refused.packet);
  EXPECT_EQ(error.code, haptic::ErrorCode::Refused);
  EXPECT_EQ(error.sequence, 2u);
  EXPECT_EQ(error.message, std::string("Session.step(depth): moves the tip 20 mm in one step (from 0 mm)").substr(0, 55));
  session.advance(1);
  const haptic::Decoded after = exchange(server.port(), haptic::PosePacket{3, 0, 0, {0.0}});
  ASSERT_TRUE(after.packet);
  ASSERT_TRUE(std::holds_alternative<haptic::StatePacket>(*after.packet));
  EXPECT_NEAR(std::get<haptic::StatePacket>(*after.packet).depth, 0.0, 1e-12);  // held where the session last took it
  server.stop();
}

// A session held for minutes between insertion and retraction replays exactly, stepped at the
// physics rate without the clock (advance): 43.6 mm in at 5 mm/s, 145 s still, 10 mm out. The
// recording keeps the commands as the doubles that were stepped. The shaft friction of a held
// needle alternates between two values from step to step (round-off small), and the force at the
// first retraction step depends on that alternation's phase: with commands rounded to 10 digits
// (the pose 0.0436 m instead of 0.043599999999999445 m) the hold shifted the phase, and the
// replay's friction differed by 1e-3 to 3e-2 N from the first retraction step on.
TEST(LiveRecording, AHoldOfMinutesReplaysExactly) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 5e-3;
  settings.limits.maxDepth = 0.0;
  live::LiveSession session(realtime2d(), settings);
  session.setDrive({1.0});
  session.advance(8720);
  session.setDrive({});
  session.advance(145000);
  session.setDrive({-1.0});
  session.advance(2000);
  const fs::path dir = scratch("live_hold");
  live::writeRecording(session.scenario(), session.log(), dir, false, 1.0, "test");
  api::Scenario again = api::Scenario::builtIn();
  const live::StepLog replayed = live::replay(dir, again);
  ASSERT_EQ(replayed.size(), session.log().size());
  std::size_t firstDifferent = replayed.size();
  for (std::size_t k = 0; k < replayed.size() && firstDifferent == replayed.size(); ++k)
    if (replayed.rows()[k].state.friction_force != session.log().rows()[k].state.friction_force) firstDifferent = k;
  EXPECT_EQ(firstDifferent, replayed.size()) << "friction differs first at step " << firstDifferent;
  EXPECT_LT(live::largestDifference(replayed.forcesTable(true), dir / "forces.csv"), 1e-9);
  EXPECT_LT(session.log().rows().back().state.friction_force, 0.0);  // retracting: the friction reversed
  fs::remove_all(dir);
}

// POST /api/drive takes the five axes as numbers in [-1, 1]; any other key, a value of another
// type or out of range is refused with the key as the field and what is allowed.
TEST(LiveWeb, DriveRefusesUnknownKeysAndWrongTypesNamingTheField) {
  const live::Drive d = live::driveFromJson(R"({"insert": 1, "rotate": -0.5, "tilt": 0})");
  EXPECT_EQ(d.insert, 1.0);
  EXPECT_EQ(d.rotate, -0.5);
  EXPECT_EQ(live::driveFromJson("{}").insert, 0.0);
  const std::pair<const char*, const char*> refused[] = {
      {R"({"insert": "fast"})", "insert"}, {R"({"warp": 9})", "warp"},       {R"({"insert": 2})", "insert"},
      {R"({"roll": true})", "roll"},       {R"({"lateral": null})", "lateral"}, {R"({"insert": [1]})", "insert"},
      {R"([1, 2])", "body"},              {"insert=1", "body"}};
  try {
    live::driveFromJson(R"({"warp": 9})");
  } catch (const needlesim::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("insert, lateral, rotate, tilt and roll"), std::string::npos) << e.what();
  }
  for (const auto& [body, field] : refused) {
    try {
      live::driveFromJson(body);
      ADD_FAILURE() << body << " was taken";
    } catch (const needlesim::InputError& e) {
      EXPECT_EQ(e.field(), field) << body;
      EXPECT_NE(std::string(e.what()).find("allowed: "), std::string::npos) << e.what();
    }
  }
  const std::string deep = R"({"insert": )" + std::string(20000, '[') + std::string(20000, ']') + "}";
  EXPECT_THROW(live::driveFromJson(deep), needlesim::InputError);  // refused, not echoed by a deep recursion
  EXPECT_THROW(live::requireNoArguments("POST /api/reset", R"({"hard": true})"), needlesim::InputError);
  EXPECT_NO_THROW(live::requireNoArguments("POST /api/reset", "{}"));
  EXPECT_NO_THROW(live::requireNoArguments("POST /api/reset", ""));
  EXPECT_EQ(live::sinceFromQuery("42"), 42u);
  EXPECT_THROW(live::sinceFromQuery("-1"), needlesim::InputError);
  EXPECT_THROW(live::sinceFromQuery("abc"), needlesim::InputError);
}

// In 3D the frame's state.tip is the tip in space: the end of the needle's centre line, out of
// the insertion plane (z) once the needle is tilted.
TEST(LiveWeb, FrameTipIsTheCentreLineEndIn3d) {
  live::LiveSettings settings;
  settings.record = true;
  settings.limits.insertSpeed = 0.02;
  settings.limits.maxDepth = 0.0;
  const api::Scenario scenario =
      api::Scenario::fromFile(fs::path(NEEDLESIM_SOURCE_DIR) / "examples/realtime3d/quick_block.yaml")
          .with({{"model.realtime3d.nodes_lateral", "5"}, {"model.realtime3d.nodes_height", "5"}, {"model.realtime3d.refinement", "1"}});
  live::LiveSession session(scenario, settings);
  session.setDrive({1.0, 0.0, 0.0, 1.0});  // insert while tilting
  session.advance(250);
  const std::vector<double> tip = live::frameJson(session, 0)["state"]["tip"].get<std::vector<double>>();
  ASSERT_EQ(tip.size(), 3u);
  api::Session reference(scenario);  // the recorded commands, for the centre line at this step
  for (const live::StepRecord& r : session.log().rows()) reference.step(live::commandFor(r.pose), r.dt);
  const std::vector<double> line = reference.needleCentreLine();
  const std::size_t end = line.size() - 3;
  EXPECT_GT(std::abs(line[end + 2]), 1e-4);  // the tilted needle ends out of the insertion plane
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(tip[static_cast<std::size_t>(c)], line[end + static_cast<std::size_t>(c)], 1e-6) << c;
}

TEST(HapticProtocol, RefusesUndefinedFlagBitsWithTheValueCode) {
  EXPECT_TRUE(haptic::decode(haptic::encode(haptic::PosePacket{5, haptic::kPoseReset, 0, {}})).packet);
  for (const std::uint32_t flags : {2u, 0x80u, 0x80000000u, 3u}) {
    const haptic::Decoded d = haptic::decode(haptic::encode(haptic::PosePacket{5, flags, 0, {}}));
    ASSERT_TRUE(d.error) << flags;
    EXPECT_FALSE(d.packet);
    EXPECT_EQ(d.error->code, haptic::ErrorCode::Value) << flags;
    EXPECT_EQ(d.error->sequence, 5u);
    EXPECT_NE(d.error->message.find("flags"), std::string::npos) << d.error->message;
    EXPECT_LE(d.error->message.size(), 55u);
  }
}

TEST(LiveNet, LoopbackHostsAreThisMachineOnly) {
  EXPECT_TRUE(live::isLoopback("127.0.0.1"));
  EXPECT_TRUE(live::isLoopback("127.3.2.1"));
  EXPECT_TRUE(live::isLoopback("localhost"));
  EXPECT_FALSE(live::isLoopback("0.0.0.0"));
  EXPECT_FALSE(live::isLoopback("192.168.1.20"));
  EXPECT_FALSE(live::isLoopback("128.0.0.1"));
}
