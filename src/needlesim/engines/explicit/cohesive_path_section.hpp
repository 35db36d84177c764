#pragma once
// Reads and checks model.explicit.cohesive.path, path_points, path_file and path_radius (the crack
// path = the needle's axis path, docs/models/cohesive.md "Crack path"): points start at the entry
// point, increase in depth (monotone along the insertion direction), stay inside the block and turn
// at most 45 deg from the insertion axis; a path other than straight needs a 2d cohesive run with a
// rigid needle and a fixed bevel. Errors name file, line, field, value and what is allowed. Part
// of model.explicit (explicit_section.cpp); needs sc.tissue, sc.needle and sc.insertion read before.
#include <string>

#include "needlesim/scenario/scenario.hpp"
#include "needlesim/scenario/yaml_section.hpp"

namespace needlesim::scenario {

// `x`: model.explicit as read so far; `c`: its cohesive section, being read.
void readCohesivePath(Section& cohesive, const ExplicitModelSpec& x, ExplicitCohesiveSpec& c, const Scenario& sc);

}  // namespace needlesim::scenario
