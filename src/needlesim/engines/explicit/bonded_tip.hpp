#pragma once
// Seed 004 section IV-B, Fig 13a read literally (`model.explicit.tip: bonded`): "we model the tissue
// and needle tip as one body but assign different material properties". A rigid bevel tip (steel
// against a soft gel) bonded into a plane-strain linear elastic block and moved a small distance along
// its axis; the tissue's resultant on the tip split as seed 004 Fig 8: P, Q on the bevel edge, q_x, q_y
// on the bottom edge. Geometry (the paper's Fig 12 is lost; assumed): the tip triangle with its heel on
// the entry face, the far face fixed, the other faces free; a uniform grid of bilinear quads, the tip
// the nodes inside the triangle (a staircase of h along the bevel, as the paper's element sets).
// docs/validation/cohesive.md "Fig 13a with the tip bonded into the tissue".
#include "needlesim/engines/engine.hpp"

namespace needlesim::explicit_fe {

struct BondedTipInput {
  double diameter = 2e-3;     // m, the needle's outer diameter d
  double bevelAngle = 0.0;    // rad
  double youngs = 25e3;       // Pa, the tissue's small-strain modulus
  double poisson = 0.45;
  double push = 0.5e-3;       // m, the tip's axial displacement
  double length = 24e-3;      // m, the block's depth W (the heel on x = 0, the far face x = W fixed)
  double width = 24e-3;       // m, y in [-width/2, width/2], the needle on |y| <= d/2
  double elementSize = 0.2e-3;  // m, the uniform grid's spacing h
  double thickness = 1e-3;    // m, the plane-strain slab's thickness
};

// The tissue's force on the tip (N, per `thickness`): axial (x, the insertion direction) and lateral
// (y, the side the bevel face looks to).
struct BondedTipForces {
  double P = 0.0, Q = 0.0;    // on the bevel edge
  double qx = 0.0, qy = 0.0;  // on the bottom edge
};

// The linear static solution (sparse LDL^T); throws SolverError when the grid holds no tip node.
BondedTipForces solveBondedTip(const BondedTipInput& in);

// The scenario's bonded tip (2D explicit model, bevel tip): the block, the needle, the tissue's first
// layer, the profile's travel and model.explicit.element_size; results P, Q, q_x, q_y (times the slab
// thickness, the needle diameter, as every 2D explicit result) and a one-row table bonded_tip.
void runBondedTip(const Scenario& sc, ResultSink& sink);
// The run's step plan: one static solve, costed as every 2D explicit run by its elements (run_cost.hpp).
StepPlan bondedTipStepPlan(const Scenario& sc);

}  // namespace needlesim::explicit_fe
