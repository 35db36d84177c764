#pragma once
// Moved to needlesim/contact/karnopp.hpp (the contact and friction laws);
// this name stays for the files that still include it.
#include "needlesim/contact/karnopp.hpp"

namespace needlesim::forces {
using contact::karnoppPerLength;
}  // namespace needlesim::forces
