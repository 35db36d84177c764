#pragma once
// The one insertion frame of every engine (docs/models/frame.md).
//
// Tissue frame: x = depth from the entry face into the block, y = across the
// block's width (in the insertion plane), z = across its height (out of the
// insertion plane); origin at the centre of the entry face, so the block spans
// x in [0, length], y in [-width/2, width/2], z in [-height/2, height/2].
// Engines whose grid starts at a block corner add cornerShift().
//
// Needle frame (right-handed, axial x lateral = outOfPlane):
//   axial      = (sin theta, cos theta, 0), theta = insertion.entry_angle, the angle
//                between the needle and the entry face: 90 deg runs along +x, a
//                smaller angle tilts the needle towards +y as it goes deeper;
//   lateral    = (-cos theta, sin theta, 0), in the insertion plane (+y at 90 deg);
//   outOfPlane = +z.
// Bevel: bevelSide(roll) = cos(phi + roll) lateral + sin(phi + roll) outOfPlane,
// phi = insertion.bevel_orientation, is the side the bevel face looks to: the heel
// lies on +bevelSide, the sharp point at -R bevelSide (needle::NeedleShape). The
// tissue's pressure on the face pushes the tip towards -bevelSide (seed 002
// section 3, seed 003 section 3.4): at bevel_orientation 0 a bevel needle is
// pushed, and bends, towards -lateral.
//
// Results (results/forces_table.hpp): force_lateral is the tissue's force on the
// needle along `lateral`, tip_deflection the tip's offset along `lateral`.
#include <Eigen/Core>

#include "needlesim/insertion/insertion_spec.hpp"

namespace needlesim::needle {

struct InsertionFrame {
  Eigen::Vector3d entry = Eigen::Vector3d::Zero();  // m, tissue frame
  Eigen::Vector3d axial = Eigen::Vector3d::UnitX();
  Eigen::Vector3d lateral = Eigen::Vector3d::UnitY();
  Eigen::Vector3d outOfPlane = Eigen::Vector3d::UnitZ();
  double bevelOrientation = 0.0;  // rad, phi

  static InsertionFrame fromInsertion(const InsertionSpec& insertion);

  // The point of the needle axis `depth` along it from the entry point.
  Eigen::Vector3d onAxis(double depth) const { return entry + depth * axial; }
  // Side the bevel face looks to after turning the needle by `roll` about its axis.
  Eigen::Vector3d bevelSide(double roll = 0.0) const;
  // The same in the insertion plane only (2D engines): +1 when the bevel looks to
  // +lateral, -1 to -lateral (the plane section of a bevel turned by roll).
  double bevelSign(double roll = 0.0) const;

  // Components of a tissue-frame vector in the needle frame.
  double axialOf(const Eigen::Vector3d& v) const { return axial.dot(v); }
  double lateralOf(const Eigen::Vector3d& v) const { return lateral.dot(v); }
  double outOfPlaneOf(const Eigen::Vector3d& v) const { return outOfPlane.dot(v); }
};

// Vector from the centre of the entry face to the block's corner origin
// (x = 0, y = -width/2, z = -height/2): add it to a centred point to get the
// point in a frame whose origin is that corner. Tissue: anything with width and
// height (a TissueSpec of scenario/scenario.hpp, which this layer does not include).
template <class Tissue>
Eigen::Vector3d cornerShift(const Tissue& tissue) {
  return {0.0, 0.5 * tissue.width, 0.5 * tissue.height};
}

}  // namespace needlesim::needle
