#pragma once
// The API boundary: internal errors become the public api:: errors with the same message.
#include <utility>

#include "needlesim/core/error.hpp"
#include "needlesim/core/progress.hpp"
#include "needlesim/needlesim.hpp"

namespace needlesim {
class MemorySink;
}

namespace needlesim::api::detail {

// The public results of a run kept in memory (api/results.cpp).
Results memoryResults(MemorySink& sink);
// Status, notes, warnings and field files of a committed results folder, into r (r.folder set).
void readFolder(Results& r);

// Runs `body` and rethrows needlesim's errors as the api:: error of the same kind.
template <class Body>
auto translated(Body&& body) -> decltype(body()) {
  try {
    return std::forward<Body>(body)();
  } catch (const needlesim::InputError& e) {
    throw InputError(e.what(), e.where().file, e.where().line, e.field());
  } catch (const needlesim::SolverError& e) {
    throw SolverError(e.what());
  } catch (const needlesim::RunInterrupted& e) {
    throw Interrupted(e.what());
  } catch (const needlesim::Error& e) {
    throw Error(e.what());
  }
}

// An InputError about an argument of an API call, worded like every input error:
// "<C++ API>: needlesim::api::<call>(<argument>): <problem> (got '<value>'); allowed: <allowed>".
[[noreturn]] void argumentError(const std::string& call, const std::string& argument, const std::string& value,
                                const std::string& problem, const std::string& allowed);

}  // namespace needlesim::api::detail
