#pragma once
// Energy-storing contact of two deformable bodies in the MPM solver
// (MpmConfig::bodyContact = Penalty; docs/models/mpm.md "Penalty contact of
// two bodies").
//
// Kept from seed 000 eqs 14-21: one velocity field per body on the grid, the
// bodies interact only where they meet, Coulomb friction limited by mu times
// the normal force with a sticking limit (eqs 19-21). Departure: the normal
// force is not the velocity-consistent impulse of eqs 15-18 at the grid
// nodes (a perfectly plastic impact of the contact-node masses), but a
// penalty force between material points of different bodies whose volumes
// overlap: each point is a sphere of diameter d_p = cbrt(V0) (its spacing),
// so the bodies touch when their surfaces (d_p/2 outside the outermost
// points) meet, and a pair p, q at distance r < d = (d_p + d_q)/2 pushes
// apart with
//   f = k delta n,  delta = d - r,  n = (x_p - x_q)/r,  k = kappa M d_p,
// M the largest P-wave modulus K + 4/3 mu of the materials (a point's face
// d_p^2 pressed by delta feels the pressure of a layer d_p/kappa thick). The
// pair potential 1/2 k delta^2 is a function of the positions only, the force
// is its gradient and enters the grid like the internal force (f_I += N_Ip f_p),
// so its power is exactly sum_p f_p . v_p of the points' grid velocities:
// the stored energy is returned (energy balance: kinetic + strain + penalty).
// Friction on a pair: f_t = -min(mu f_n, m_r |v_t| / dt) v_t / |v_t| (the
// sticking force of the pair's reduced mass, eq 19, limited by eq 20), with
// f_n the pair force along the bodies' surface normal (mass gradients at the
// pair's midpoint) and v_t the sliding velocity of the two grid fields at the
// two points; it works only while the faces slide. While pairs touch, the
// time step resolves the pair oscillator (stepLimit).
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace needlesim::mpm {

// Totals of one step.
struct PenaltyTally {
  double energy = 0.0;       // J, stored penalty energy sum 1/2 k delta^2
  double penetration = 0.0;  // m, largest overlap delta
  int pairs = 0;             // pairs in contact
  int close = 0;             // pairs that would touch within two steps at their approach speed
};

// Scratch and parameters of the pair search; the forces are computed and
// scattered by MpmSolver::penaltyForces (penalty_contact.cpp).
class PairPenalty {
 public:
  // stiffness k (N/m per pair), the radius of each point's volume (half its
  // spacing, cbrt(V0) / 2; a pair touches at the sum of the two), the
  // smallest reduced mass of a pair m_r (kg), threads.
  PairPenalty(double stiffness, std::vector<double> radius, double reducedMass, int threads);
  // Time step that resolves the pair oscillator, alpha / omega with
  // omega = sqrt(k / m_r), while pairs were in contact in the last step
  // (infinite otherwise, or for alpha <= 0).
  double stepLimit(double alpha) const;
  double stiffness() const { return k_; }
  const PenaltyTally& tally() const { return tally_; }
  double pairEnergy(double delta) const;  // J, potential of one pair at overlap delta
  double frictionWork() const;  // J, kinetic energy friction removed since resetFriction
  void resetFriction();

 private:
  friend class MpmSolver;
  double k_;
  std::vector<double> radius_;  // per point
  double omega_;
  // Cell lists (CSR, key body * nodes + cell) of the candidate points: start_,
  // items_; cand_ and candKey_ the candidates with their keys, cells0_ the
  // cells that hold candidates of body 0 (the pair search visits these).
  std::vector<std::uint32_t> start_, items_, cand_, candKey_, cursor_, cells0_, cells1_;
  std::vector<double> box_;  // 6 per cell (body-1 cells with candidates): bounding box of their points, lo (3), hi (3)
  double rmax_ = 0.0;        // largest radius
  // 3 per item slot of items_: the pair forces (body-0 slots from the thread
  // that owns the cell, body-1 slots the reactions of thread 0); reaction_[t]
  // holds those of thread t > 0.
  std::vector<double> force_;
  std::vector<std::vector<double>> reaction_;
  // Pairs in contact found by each thread: slots of p and q, normal n (3),
  // force magnitude; the field velocities (3 per slot) of the points in a
  // pair, each computed once (need_ marks them).
  struct Contact {
    std::uint32_t sp, sq;
    double n[3], fn;
  };
  std::vector<std::vector<Contact>> contacts_;
  std::vector<double> vfield_;
  std::vector<std::uint8_t> need_;
  std::vector<PenaltyTally> thread_;                 // per thread
  std::vector<std::vector<std::array<std::uint32_t, 2>>> pairs_;  // per thread: pairs in contact (p of body 0)
  std::vector<double> friction_;                     // per thread (stride 8): friction work
  PenaltyTally tally_;
};

}  // namespace needlesim::mpm
