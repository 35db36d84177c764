// api::plan (docs/planning.md) through the shared library: the gel example planned in memory and
// into a folder; a scenario without a plan section refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include <unistd.h>

#include "needlesim/needlesim.hpp"

namespace api = needlesim::api;

TEST(ApiPlan, PlansTheGelExampleInMemoryAndIntoAFolder) {
  const auto sc = api::Scenario::fromFile(std::string(NEEDLESIM_SOURCE_DIR) + "/examples/planning/gel_block.yaml");
  const api::Results r = api::plan(sc);
  EXPECT_EQ(r.value("feasible").value, 1.0);
  EXPECT_GE(r.value("clearance_vessel").value, 2e-3);
  EXPECT_GT(r.table("path").rows(), 10u);
  EXPECT_EQ(r.table("plan").rows(), 1u);
  const std::filesystem::path out = std::filesystem::temp_directory_path() / ("api_plan_" + std::to_string(::getpid()));
  std::filesystem::remove_all(out);
  const api::Results f = api::plan(sc, out);
  EXPECT_EQ(f.status, "complete");
  EXPECT_EQ(f.value("entry_angle").value, r.value("entry_angle").value);  // the search is seeded
  ASSERT_EQ(f.fieldFiles.size(), 1u);
  EXPECT_EQ(f.fieldFiles[0].filename(), "planned_path.xdmf");
  std::filesystem::remove_all(out);
}

TEST(ApiPlan, AScenarioWithoutAPlanSectionIsAnInputError) {
  EXPECT_THROW(api::plan(api::Scenario::builtIn()), api::InputError);
}
