#pragma once
// A lower layer that includes a higher one: scripts/check_layers.py must refuse it.
#include "needlesim/scenario/scenario.hpp"
