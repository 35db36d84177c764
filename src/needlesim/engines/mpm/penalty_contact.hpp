#pragma once
// Energy-storing contact of two deformable bodies in the MPM solver
// (docs/models/mpm.md "Penalty contact of two bodies").
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
// apart along n = (x_p - x_q)/r with, delta = d - r the overlap,
//   f = k delta                      for delta <= delta_s = 0.3 d,
//   f = k delta (G / r)^6, G = d - delta_s,   beyond (barrier),
// k = kappa M d_p, M the largest P-wave modulus K + 4/3 mu of the materials
// (a point's face d_p^2 pressed by delta feels the pressure of a layer
// d_p/kappa thick). The barrier is a departure for robustness: with the
// linear law alone a face pressure p >= kappa M drove the overlap to d_p and
// the points passed through each other (two spheres at 2 x 0.5 m/s, Hertz
// p0 = 0.2 M: drift 17.9 % with mu 0.3); with it f(d/2) = 3.8 k d (a pressure 3.8 kappa
// M held at half a spacing) and f -> infinity only as r -> 0, finite for
// any r > 0. The flat block impact (overlap 0.29 d) stays in the linear part.
// f is continuous (its slope steps from k to k (1 + 6 delta_s / G) = 3.6 k at
// the onset; the step limit follows it) and derives
// from the pair potential U(delta) = int_0^delta f (closed form, pairEnergy),
// a function of the positions only; the force enters the grid like the
// internal force (f_I += N_Ip f_p), so its power is exactly sum_p f_p . v_p of
// the points' grid velocities: the stored energy is returned (energy
// balance: kinetic + strain + penalty).
// Friction on a pair: f_t = -min(mu f_n, m_r |v_t| / dt) v_t / |v_t| (the
// sticking force of the pair's reduced mass, eq 19, limited by eq 20;
// contact::coulombPair; the pair law: contact/penalty.hpp), with
// f_n the pair force along the bodies' surface normal (mass gradients at the
// pair's midpoint) and v_t the sliding velocity of the two grid fields at the
// two points; it works only while the faces slide. While pairs touch, the
// time step resolves the pair oscillator at the largest tangent stiffness
// df/ddelta = k (G/r)^6 (1 + 6 delta / r) of the step (stepLimit): the step
// shrinks with the gap r, so a pair cannot cross r = 0 in one step.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>


namespace needlesim::mpm {

// Totals of one step.
struct PenaltyTally {
  double energy = 0.0;       // J, stored penalty energy, sum of U(delta) over the pairs
  double penetration = 0.0;  // m, largest overlap delta
  double tangent = 0.0;      // N/m, largest tangent stiffness df/ddelta of a pair in contact
  double travel = std::numeric_limits<double>::infinity();  // s, smallest r / v_n of an approaching pair in contact or close
  int pairs = 0;             // pairs in contact
  int close = 0;             // pairs that would touch within two steps at their approach speed
};

// Scratch and parameters of the pair search; the forces are computed and
// scattered by MpmSolver::penaltyForces (penalty_contact.cpp).
// Where thread `tid` adds the values (`width` per slot) it computes for the
// body-1 slots [first1, nc) of the other threads' pairs: thread 0 straight
// into `own` (indexed by slot), the others into their own `buffer`, zeroed,
// indexed from first1 (slot s at base[width (s - from)]); summed after a barrier.
struct ReactionSink {
  double* base;
  std::size_t from;
};
inline ReactionSink reactionSink(double* own, std::vector<double>& buffer, std::size_t width, std::size_t tid,
                                 std::size_t first1, std::size_t nc) {
  if (tid == 0) return {own, 0};
  buffer.assign(width * (nc - first1), 0.0);
  return {buffer.data(), first1};
}

class PairPenalty {
 public:
  // stiffness k (N/m per pair), the radius of each point's volume (half its
  // spacing, cbrt(V0) / 2; a pair touches at the sum of the two), the
  // smallest reduced mass of a pair m_r (kg), threads.
  PairPenalty(double stiffness, std::vector<double> radius, double reducedMass, int threads);
  // Time step that resolves the pair oscillator and the approach, the
  // smaller of alpha / omega with omega = sqrt(k_t / m_r), k_t the largest
  // tangent stiffness of a pair at the start or end of the last step, and
  // alpha r / v_n, the time in which an approaching pair closes the fraction
  // alpha of its distance r, while pairs were in contact or close in it
  // (infinite otherwise, or for alpha <= 0). MpmSolver::penaltyForces lowers
  // the step further to the same limit of the step's own start (limit).
  double stepLimit(double alpha) const { return limit(tally_, alpha); }
  double limit(const PenaltyTally& t, double alpha) const;
  double stiffness() const { return k_; }
  const PenaltyTally& tally() const { return tally_; }
  // The pair law at overlap delta of a pair with contact distance d (m):
  // force (N), tangent stiffness df/ddelta (N/m), potential U (J); for
  // 0 < delta < d (r = d - delta > 0).
  double pairForce(double delta, double d) const;
  double pairTangent(double delta, double d) const;
  double pairEnergy(double delta, double d) const;
  double frictionWork() const;  // J, kinetic energy friction removed since resetFriction
  void resetFriction();

 private:
  friend class MpmSolver;
  double k_;
  std::vector<double> radius_;  // per point
  double mr_;                   // kg, smallest reduced mass of a pair
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
  std::size_t first1_ = 0;  // slots [first1_, cand_.size()) hold body 1
  // Shared by both laws: the candidates (nearCell[p] != ~0: p's cell) binned
  // per body and cell (serial counting sort into start_, items_, cells0_,
  // cells1_); the occupied body-1 cells within `reach` cells of the body-0
  // cell c0 (slot ranges lo, hi and their boxes bb; returns how many).
  void bin(const std::uint32_t* nearCell, const std::uint8_t* body, std::size_t n, std::size_t nodes);
  PenaltyTally sum() const;  // totals of the threads' tallies
  void cellBoxes(const double* x, std::size_t stride, std::size_t nodes);  // positions x[stride p + d]
  int nearCells(std::size_t c0, int reach, std::size_t nodes, std::size_t n1, std::size_t n2, const long long* lim,
                std::uint32_t* lo, std::uint32_t* hi, const double** bb) const;
};

}  // namespace needlesim::mpm
