// The message of the InputError a call must throw (an empty text and a test failure when it throws none).
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::test {

inline std::string refusal(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an InputError";
  return "";
}

}  // namespace needlesim::test
