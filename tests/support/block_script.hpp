#pragma once
// The generated block's square grid written as a Gmsh script (transfinite quads with a node row on
// the path y = 0, physical surface "gel"), shared by the engines' imported-geometry tests.
#include <fmt/format.h>

#include <string>

namespace needlesim::test_support {

// A block `side` m square (x from 0, y centred) of intervals x intervals quads, in units of `scale` m.
inline std::string blockScript(double side, int intervals, double scale) {
  return fmt::format(R"(L = {0}; W = {0}; n = {1};
Point(1) = {{0, -W/2, 0}}; Point(2) = {{L, -W/2, 0}}; Point(3) = {{L, W/2, 0}}; Point(4) = {{0, W/2, 0}};
Line(1) = {{1, 2}}; Line(2) = {{2, 3}}; Line(3) = {{3, 4}}; Line(4) = {{4, 1}};
Curve Loop(1) = {{1, 2, 3, 4}}; Plane Surface(1) = {{1}};
Transfinite Curve {{1, 2, 3, 4}} = n + 1; Transfinite Surface {{1}}; Recombine Surface {{1}};
Physical Surface("gel") = {{1}};
)",
                     side / scale, intervals);
}

}  // namespace needlesim::test_support
