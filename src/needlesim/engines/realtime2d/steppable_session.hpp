#pragma once
// The realtime2d engine's Session as a steppable session (engines/session.hpp).
#include <memory>

#include "needlesim/engines/session.hpp"

namespace needlesim::engines {
std::unique_ptr<SteppableSession> openRealtime2dSession(const Scenario& scenario);
}  // namespace needlesim::engines
