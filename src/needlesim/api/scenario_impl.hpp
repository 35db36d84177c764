#pragma once
// What an api::Scenario holds: the typed scenario and the YAML it was read from.
#include <string>

#include "needlesim/needlesim.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::api {

struct Scenario::Impl {
  needlesim::Scenario scenario;
  std::string yaml;
};

}  // namespace needlesim::api
