#pragma once
// The lumped tip forces of the real-time engines (seed 003 section 3.2), on a line of path
// nodes along the reference needle axis: pre-puncture stiffness of each layer boundary
// (eq 3.16) until its puncture threshold, then constant cutting (eq 3.24) while the tip
// advances into uncut tissue. Loads go to the axial component (c = 0) of the path nodes,
// path load k = comps i + c (tissue_dynamics.hpp).
#include <Eigen/Core>
#include <vector>

#include "needlesim/forces/stiffness.hpp"

namespace needlesim::realtime {

// Axial base motion of one step.
struct AxialMotion {
  double ds = 0.0, v_ax = 0.0;  // m, m/s
  double s_tip = 0.0;           // m, tip along the reference axis
};

// A layer boundary the tip must puncture (eq 3.16 with the layer's material).
struct Membrane {
  double s = 0.0;          // m, along the reference axis
  double threshold = 0.0;  // N
  forces::StiffnessLaw law;
  int node = 0;            // path node that takes the indentation load
};

class TipForces {
 public:
  TipForces() = default;
  // path_s: reference axial positions of the path nodes (ascending); membranes: the entry face first.
  TipForces(std::vector<Membrane> membranes, std::vector<double> path_s, int comps);
  // Phase A: the tip indents the next unpunctured boundary; returns the indentation force
  // (0 once punctured) and adds it to fK.
  double press(double s_tip, Eigen::VectorXd& fK, bool& punctured_now);
  // Cutting force `Fcut` of the tissue at the tip, applied only while the tip advances into
  // uncut tissue (|v| inside the static band holds it; retraction releases it); split
  // linearly between the path nodes around the tip. Returns the applied force.
  double cut(const AxialMotion& mo, double Fcut, double band, double s_exit, Eigen::VectorXd& fK);
  bool entered() const { return pending_ > 0; }  // the entry face is punctured
  bool pressing() const { return pressing_; }
  // How far along the axis the coupled nodes may reach: short of a boundary being pressed.
  double reach(double s_tip) const;
  const std::vector<Membrane>& membranes() const { return membranes_; }
  // Nearest path node to the axial position s.
  static int nearestNode(const std::vector<double>& path_s, double s);

 private:
  std::vector<Membrane> membranes_;
  std::vector<double> s_;
  int comps_ = 2;
  std::size_t pending_ = 0;  // first membrane not yet punctured
  bool pressing_ = false;
  double front_ = 0.0;
};

}  // namespace needlesim::realtime
