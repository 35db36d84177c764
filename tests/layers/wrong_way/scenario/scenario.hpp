#pragma once
// A higher layer that includes a lower one: allowed.
#include "needlesim/core/units.hpp"
