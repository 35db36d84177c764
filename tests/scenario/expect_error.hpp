#pragma once
// Helpers of the scenario reader tests: edit a scenario text, expect an InputError.
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "needlesim/core/error.hpp"
#include "needlesim/scenario/reader.hpp"

namespace needlesim::test {

// `s` with the first `from` replaced by `to` (a test failure when `from` is not there).
inline std::string replaced(std::string s, const std::string& from, const std::string& to) {
  auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) s.replace(pos, from.size(), to);
  return s;
}

// Reads `yaml` (as case.yaml) expecting an InputError whose message holds every `parts`.
inline std::string expectError(const std::string& yaml, std::initializer_list<std::string> parts) {
  try {
    scenario::readText(yaml, "case.yaml");
  } catch (const InputError& e) {
    std::string msg = e.what();
    for (const auto& p : parts) EXPECT_NE(msg.find(p), std::string::npos) << "missing '" << p << "' in: " << msg;
    return msg;
  }
  ADD_FAILURE() << "no error for:\n" << yaml;
  return {};
}

}  // namespace needlesim::test
