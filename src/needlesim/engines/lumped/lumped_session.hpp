#pragma once
// The lumped force model (seed 003 section 3.2) as a steppable session (engines/session.hpp).
#include <memory>

#include "needlesim/engines/session.hpp"

namespace needlesim::engines {
std::unique_ptr<SteppableSession> openLumpedSession(const Scenario& scenario);
}  // namespace needlesim::engines
