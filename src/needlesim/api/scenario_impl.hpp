#pragma once
// What an api::Scenario holds: the typed scenario, the YAML it was read from and the
// folder its relative data paths resolve from.
#include <filesystem>
#include <memory>
#include <string>
#include <utility>

#include "needlesim/needlesim.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::api {

struct Scenario::Impl {
  needlesim::Scenario scenario;
  std::string yaml;
  std::filesystem::path folder;  // the scenario file's folder; empty for YAML text
};

namespace detail {
struct ScenarioAccess {
  // A Scenario from the typed scenario, the YAML text it was read from and the folder of its file.
  static Scenario make(needlesim::Scenario typed, std::string yaml, std::filesystem::path folder = {}) {
    return Scenario(std::make_shared<const Scenario::Impl>(
        Scenario::Impl{std::move(typed), std::move(yaml), std::move(folder)}));
  }
  static const needlesim::Scenario& typed(const Scenario& s) { return s.impl_->scenario; }
};
}  // namespace detail

}  // namespace needlesim::api
