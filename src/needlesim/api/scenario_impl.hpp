#pragma once
// What an api::Scenario holds: the typed scenario and the YAML it was read from.
#include <memory>
#include <string>
#include <utility>

#include "needlesim/needlesim.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::api {

struct Scenario::Impl {
  needlesim::Scenario scenario;
  std::string yaml;
};

namespace detail {
struct ScenarioAccess {
  // A Scenario from the typed scenario and the YAML text it was read from.
  static Scenario make(needlesim::Scenario typed, std::string yaml) {
    return Scenario(std::make_shared<const Scenario::Impl>(Scenario::Impl{std::move(typed), std::move(yaml)}));
  }
  static const needlesim::Scenario& typed(const Scenario& s) { return s.impl_->scenario; }
};
}  // namespace detail

}  // namespace needlesim::api
