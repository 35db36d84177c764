#pragma once
// The scenario's sleeve seam (model.explicit.cohesive.seam: sleeve; docs/models/cohesive.md
// "Sleeve seam"): the O-grid block of mesh_sleeve.hpp sized from the scenario.
#include "needlesim/engines/explicit/mesh_sleeve.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/needle/surface_mesh.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::explicit_fe {

// Block x in [0, length] (depth), y across the width (axis at entry_offset), z across the height;
// cells of element_size around the sleeve (4 x ceil(pi r_s / (2 h)) around, core layers of ~h),
// graded by `grading` to max_element_size; axial stations as the plane seam's block; the sleeve
// split down to the deepest tip position plus two cells. r_s = cohesive.sleeve_radius or the
// wall's mid radius. Throws Error for a solid or non-bevel needle, 2D, a non-hex8 element.
SleeveMesh sleeveMeshFor(const Scenario& sc, const needle::NeedleShape& shape, double& radius);

// Of the sleeve pairs the needle wall's edge has passed (cohesive_sleeve.hpp sleeveEdge), the fraction
// whose core-side node lies inside the bore (r <= r_i + 5 % of the wall) and whose outer node lies
// outside the wall (r >= r_o - 5 %): the core entering the bore. -1 when the edge passed no pair.
double sleeveCoreInBore(ExplicitSolver& solver);

}  // namespace needlesim::explicit_fe
