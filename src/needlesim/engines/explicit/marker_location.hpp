#pragma once
// Tissue markers of the explicit engine (model.explicit.markers, declared as the real-time engines'
// markers): a marker is the material point at its reference position, located once in the element
// that holds it; its displacement is the element's shape-function interpolation of its nodes'
// (isoparametric quad4 / hex8, barycentric tri3 / tet4; Belytschko et al. box 6.1's total Lagrangian
// field). Output through engines/realtime/markers.hpp: markers.csv and marker_<name>_u*_{max,final}.
#include <Eigen/Core>
#include <optional>

#include "needlesim/engines/explicit/mesh.hpp"
#include "needlesim/engines/realtime/markers.hpp"

namespace needlesim::explicit_fe {

// The element holding the reference point X (tissue frame, m; z ignored in 2D) and the shape
// functions at X, or nothing when no element holds it.
std::optional<engines::MarkerPoint> locateMarker(const Mesh& mesh, const Eigen::Vector3d& X);

}  // namespace needlesim::explicit_fe
