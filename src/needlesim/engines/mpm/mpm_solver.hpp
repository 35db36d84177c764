#pragma once
// Explicit 3D material point method (seed 000 eqs 1-4) with rigid grid
// contact (eqs 14-22), CFEMP (eqs 22-24), the pair penalty contact of two
// deformable bodies, CFL time step (eqs 25-27) and mass scaling (eq 28).
// Particles are an array of 256-byte records; the background grid is a dense
// box that is reset every step. The solver owns the particles and the grid
// and steps the passes, each in its own file: particle_to_grid.cpp,
// penalty_contact.cpp, grid_update.cpp (with the rigid grid contact),
// cfemp_contact.cpp, needle_cut.cpp, grid_to_particle.cpp, fbar.cpp; the
// parts with state of their own are block_colouring.hpp (the race-free scatter
// order), near_bodies.hpp, grid_boundaries.hpp, phase_clock.hpp and
// cfemp_contact.hpp. Interpretations: docs/models/mpm.md.
#include <Eigen/Core>
#include <Eigen/LU>
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "needlesim/engines/mpm/block_colouring.hpp"
#include "needlesim/engines/mpm/cfemp_contact.hpp"
#include "needlesim/engines/mpm/grid_boundaries.hpp"
#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/mpm_config.hpp"
#include "needlesim/engines/mpm/mpm_material.hpp"
#include "needlesim/engines/mpm/near_bodies.hpp"
#include "needlesim/engines/mpm/penalty_contact.hpp"
#include "needlesim/engines/mpm/phase_clock.hpp"
#include "needlesim/engines/mpm/rigid_body.hpp"
#include "needlesim/io/binary_state.hpp"

struct NsMpmBackend;  // cuda/mpm_device_abi.h

namespace needlesim::mpm {

class DeviceRun;  // cuda/device_bridge.cpp

namespace lanes {
template <int S>
struct Stencil4;  // support_lanes.hpp
}  // namespace lanes

class MpmSolver {
 public:
  explicit MpmSolver(const MpmConfig& cfg);

  int addMaterial(const MpmMaterial& m);
  int addRigid(const RigidBody& r);
  RigidBody& rigid(int i) { return rigids_[static_cast<std::size_t>(i)]; }
  // Fills the box [lo, hi] with particles on a lattice of spacing dp (nper along each edge
  // implied); returns the index of the first new particle.
  std::size_t addBlock(const Vec3& lo, const Vec3& hi, double dp, int material, int body,
                       const Vec3& velocity = Vec3::Zero());
  // The points of `lattice` whose material[index] >= 0, with that material and body[index], in
  // addBlock's order; returns the index of the first new particle.
  std::size_t addLattice(const Lattice& lattice, const std::vector<int>& material, const std::vector<int>& body);
  // One material point of the given volume (its spacing, the cube root, enters
  // the particle spacing as addBlock's does); returns its index. For shapes
  // other than boxes (spheres, imported point clouds).
  std::size_t addParticle(const Vec3& x, double volume, int material, int body, const Vec3& velocity = Vec3::Zero());
  // Before finalize: moves point p to another material (its mass follows the
  // density) and body.
  void reassign(std::size_t p, int material, int body);
  // Call once after adding everything (sizes scratch; no allocation afterwards).
  void finalize();

  // One explicit step; returns dt used. Throws SolverError with cause and remedy.
  StepReport step();
  double stableTimeStep() const;  // eqs 25-27 at the current state
  double time() const { return time_; }
  long long steps() const { return steps_; }
  const RigidForce& rigidForce(int i) const { return rforce_[static_cast<std::size_t>(i)]; }
  StepReport lastReport() const { return last_; }

  // Particle data (SoA).
  std::size_t size() const { return P_.size(); }
  Vec3 position(std::size_t p) const { return {P_[p].x[0], P_[p].x[1], P_[p].x[2]}; }
  Vec3 velocity(std::size_t p) const { return {P_[p].v[0], P_[p].v[1], P_[p].v[2]}; }
  Mat3 defGrad(std::size_t p) const {
    Mat3 F;
    for (int c = 0; c < 9; ++c) F(c / 3, c % 3) = P_[p].F[c];
    return F;
  }
  Mat3 cauchy(std::size_t p) const;
  double mass(std::size_t p) const { return P_[p].mass; }           // scaled
  double volume0(std::size_t p) const { return P_[p].vol0; }
  int body(std::size_t p) const { return body_[p]; }
  int material(std::size_t p) const { return mat_[p]; }
  double particleSpacing() const { return dp_; }
  void setVelocity(std::size_t p, const Vec3& v) { P_[p].v[0] = v.x(); P_[p].v[1] = v.y(); P_[p].v[2] = v.z(); }
  void setPosition(std::size_t p, const Vec3& x) {  // tests (contactForces); the next step sorts the points again
    P_[p].x[0] = x.x(); P_[p].x[1] = x.y(); P_[p].x[2] = x.z();
    scatter_.invalidate();
  }
  const MpmConfig& config() const { return cfg_; }
  int threads() const { return nthreads_; }
  // The block colouring of the scatters for a team of `team` threads
  // (block_colouring.hpp; one thread: creation order, one pass).
  using ScatterPlan = mpm::ScatterPlan;
  ScatterPlan scatterPlan(int team) const;
  int scatterThreads() const { return scatterThreads_; }  // threads that scattered points in the last p2g
  // Wall time and process CPU time (all threads) of each phase of step(),
  // summed over the steps since finalize or the last resetPhaseTimes (s);
  // bench_mpm --phases prints them per step.
  using Phase = PhaseClock::Phase;
  using enum PhaseClock::Phase;
  static const char* phaseName(int phase) { return PhaseClock::name(phase); }
  const std::array<double, kPhases>& phaseTimes() const { return clock_.wall(); }
  const std::array<double, kPhases>& phaseCpuTimes() const { return clock_.cpu(); }
  // Of the particle passes (kScatter, kRemap, kG2P): the time each thread
  // worked in them, barrier waits left out (s, summed as phaseTimes); the
  // largest over the mean is the imbalance of the work, not of the points.
  std::vector<double> threadBusy(Phase phase) const { return clock_.busy(phase, nthreads_); }
  void resetPhaseTimes() { clock_.reset(); }
  // Points whose support the needle's cut crosses this step (planCut; tests).
  std::size_t cutPoints() const;
  // Tests: the two-body contact forces (pair penalty, without
  // friction) on every point at the current positions, and the contact energy
  // there (J); the solver's state is unchanged (penalty_contact.cpp).
  double contactForces(std::vector<Vec3>& force);

 private:
  void checkIds(int material, int body) const;
  void pushParticle(const Vec3& x, const Vec3& v, double mass, double volume, int material, int body);
  void setUpPairContact();   // finalize
  void checkInitialState();  // finalize
  PointPositions positions() const;
  // The passes of step(), each for the set-up's shape, bodies and update scheme.
  void particleToGrid();                                  // particle_to_grid.cpp
  void remapMomentum();                                   // grid_to_particle.cpp
  void gridToParticle(double& ek, double& ei, double& vmax);  // grid_to_particle.cpp
  void cfempContact(bool first);                          // cfemp_contact.cpp
  template <int S, bool Grad> void p2g();
  struct NeedleAxis;
  std::array<NeedleAxis, 8> needleAxes(double gapReach) const;  // p2g
  template <int S, bool Grad>
  void scatterPoint(std::size_t p, const lanes::Stencil4<S>& st, bool needG,
                    double* __restrict rec, double* __restrict grad, std::size_t n1, std::size_t n2);  // p2g
  template <int S> void g2pRemap();
  template <int S> void surfaceContact(bool first);
  void findSurfacePairs(std::size_t r);  // surfaceContact
  template <int S, bool Usl> void g2pFinal(double& ek, double& ei, double& vmax);
  struct GridSums;
  template <int S, bool Usl>
  static GridSums gatherGridSums(const lanes::Stencil4<S>& st, const double* __restrict vel, std::size_t off,
                                 std::size_t n1, std::size_t n2);  // g2pFinal
  template <bool Usl> double advancePoint(std::size_t p, const GridSums& g, double dt, double flip);  // g2pFinal
  template <int S>
  int checkAdvanced(std::size_t p, double J, double speed2, const double* o, double invh, const double* limEnd,
                    std::size_t n1, const int* baseLo, const int* baseHi, std::uint64_t* occ,
                    std::size_t occW, bool& strayed);  // g2pFinal
  void stressChunk(const std::size_t* ready, std::size_t nready, double& ei, double& vmax);  // g2pFinal
  void gridUpdate();
  void planGridRows();                                                               // gridUpdate
  std::pair<std::size_t, std::size_t> momentumUpdateRow(std::size_t q, bool nodeWise);  // gridUpdate
  void clearOutsideHull(std::size_t q, std::size_t h0, std::size_t h1);              // gridUpdate
  bool contactOnRow(std::size_t q, std::size_t h0, std::size_t h1);                  // gridUpdate
  void sumRigidForces(std::size_t touchLo, std::size_t touchHi);  // gridUpdate
  bool rigidContactAt(std::size_t r, std::size_t I, const Vec3& xI, const double* mb);  // gridUpdate
  void penaltyForces();           // penalty_contact.cpp
  void penaltyPairsOfCell(std::size_t c0, std::size_t tid, double dt0, double mu);  // penaltyForces
  void penaltyPairForces(std::size_t tid, double mu, double dt);                    // penaltyForces
  void penaltyEnergyAfterStep();  // penalty_contact.cpp
  void scatterContact(std::size_t tid);  // penalty_contact.cpp
  bool surfaceNormal(const double* x, double* m) const;  // penalty_contact.cpp
  double pairFriction(std::size_t p, std::size_t q, const double* n, double fn, double mu, double dt,
                      const double* vp, const double* vq, double* f) const;  // penalty_contact.cpp
  void fieldVelocity(std::size_t p, const double* rec, std::size_t NR, double* v) const;  // penalty_contact.cpp
  void remapUpdate(bool clear);
  // Needle cut (needle_cut.cpp, docs/models/mpm.md "Parting contact"): per
  // point the support nodes across the cut, and the point passes over the
  // remaining nodes with renormalised weights.
  struct CutSupport;
  void planCut();                                                                   // step
  void cutSupport(std::size_t p, CutSupport& cs) const;
  void scatterCutPoint(std::size_t p, bool needG);                  // p2g
  void remapCutPoint(std::size_t p, double flip);                                  // g2pRemap
  void gatherCutPoint(std::size_t p, std::size_t off, bool usl, double* an, double* ao, double* L) const;  // g2pFinal
  GridSums cutGridSums(std::size_t p, std::size_t off, bool usl) const;           // g2pFinal
  int cutSurfaceWeights(std::size_t p, std::size_t* node, double* w) const;       // surfaceContact
  bool wallLipNormal(std::size_t r, const Vec3& x, Vec3& n) const;                // rigidContactAt, findSurfacePairs
  bool bevelLipFloor(std::size_t r, const Vec3& xl, double& gap, Vec3& nl, bool& onFace) const;  // findSurfacePairs
  void zeroGrid(int t, int T);
  void stress(std::size_t p, const Mat3& F, double& energy, double& wave);
  void fbarStress(double& ei, double& vmax);  // fbar.cpp
  [[noreturn]] void fail(std::size_t p, int cause) const;

  MpmConfig cfg_;
  std::vector<MpmMaterial> mats_;
  std::vector<RigidBody> rigids_;
  // particles
  // One material point in four cache lines (array of structures): every
  // particle pass streams one contiguous record instead of ~30 arrays, which
  // the hardware prefetchers could not all follow (docs/performance.md).
  // The scatter reads the first two lines only.
  struct alignas(64) Point {
    double x[3], v[3];  // position, velocity
    double mass;        // scaled (eq 28)
    double vol;         // current volume V0 det F (the scatter's -V sigma)
    double sig[6];      // Cauchy stress, Voigt 11 22 33 12 23 13
    double vol0;        // reference volume
    double pad0;
    double vg[3];       // MUSL: sum_I N_Ip v_I (new grid velocity) from g2pRemap
    double F[9];        // deformation gradient, row major
    double pad1[4];
  };
  static_assert(sizeof(Point) == 256);
  std::vector<Point> P_;
  std::vector<std::uint8_t> body_, mat_;
  double dp_ = 0.0;
  // grid
  int nn_[3] = {0, 0, 0};
  std::size_t nodes_ = 0;
  int nthreads_ = 1;
  // Grid record of one node of one body, nr_ = 8 doubles (one cache line):
  // mass, momentum (3), force (3), pad. Two bodies keep the mass gradient (3)
  // in a second array of 8 doubles per node per body, written only by the points near the other
  // body (p2g), so the scatter of all other points touches half the memory.
  struct Buf {
    grid::LineVector<double> rec;   // nr_ per node per body (64-byte aligned records)
    grid::LineVector<double> grad;  // two bodies: 8 per node per body (grid::kG)
    std::vector<double> gmin;      // per node per rigid
    std::vector<std::uint8_t> gmat;  // per node per rigid: material of the point of the smallest gap (materialFriction_)
  };
  std::vector<Buf> buf_;                // one shared grid (buf_[0])
  BlockColouring scatter_;              // the order of the particle passes (block_colouring.hpp)
  int scatterThreads_ = 1;
  PhaseClock clock_;
  bool gridClean_ = false;              // the records are all zero (remapUpdate cleared them)
  int nr_ = 8;
  grid::LineVector<double> vel_;        // per node per body: v_new (3), pad, v_old (3), pad
  GridBoundaries bounds_;               // fixed components and dashpots per node (grid_boundaries.hpp)
  std::vector<std::uint8_t> active_;    // per node: rigid contact flags of the first update
  std::vector<double> rnormal_;         // per node per rigid: normal (3) used in the first update
  std::vector<RigidForce> rforce_;
  // Per material its rigidFriction; empty when no material sets one (every
  // contact node then uses the rigid body's coefficient).
  std::vector<double> materialFriction_;
  double rigidFriction(std::size_t r, std::size_t I) const;
  // Grid passes (gridUpdate, remapUpdate): per body and (i, j) row the span
  // [k0, k1) of the nodes with mass, this step's and the last one's (outside
  // its spans a row holds zero velocities and contact flags); the cumulative
  // work per row for the threads' shares; per rigid, node and body the
  // impulse of the rigid contact (force summed in node order).
  std::vector<std::uint32_t> rowSpan_, rowSpanPrev_;  // 2 per body per row
  std::vector<std::uint64_t> rowWork_;                // rows + 1
  std::vector<double> rimp_;                          // 3 per rigid per node per body
  double rigidGap_ = 0.0;               // eq 22 gap of the rigid contact: half the particle spacing, m
  std::optional<PairPenalty> penalty_;  // two bodies (penalty_contact.cpp)
  Vec3 nodePosition(std::size_t I) const;
  NearBodies nearBodies_;               // two bodies: the cells near the other body (near_bodies.hpp)
  // Two bodies: per point, its cell index (i n1 + j) n2 + k when the other
  // body occupies one of the 27 cells around it (NearBodies::near1, set by p2g: the
  // penalty contact's candidates), else kNotNear.
  static constexpr std::uint32_t kNotNear = ~std::uint32_t{0};
  std::vector<std::uint32_t> nearCell_;
  std::vector<std::uint32_t> cellOf_;   // F-bar: cell of each particle
  std::vector<double> cellJ_;           // F-bar: per cell sum V0 J, sum V0
  // CFEMP (eqs 22-24, cfemp_contact.hpp).
  std::vector<NeedleSurface> surf_;     // per rigid (empty for grid contact)
  struct SurfacePair { std::size_t p; Vec3 n; bool tip; };
  std::vector<SurfacePair> pairs_;      // CFEMP contacts of the current step
  // Needle cut (planCut): the needle that parts the tissue (-1: none), and per
  // point the support nodes across its cut, bit 9 i + 3 j + k (0: none).
  int cutRigid_ = -1;
  std::vector<std::uint32_t> cutMask_;
  double dt_ = 0.0, time_ = 0.0, maxSpeed_ = 0.0;
  long long steps_ = 0;
  StepReport last_;
  bool finalized_ = false;
  std::size_t badParticle_ = 0;

 public:
  // Checkpoints (solver_state.cpp, docs/models/mpm.md "Checkpoints"): the
  // state that carries from one step to the next, so that a solver set up
  // the same way (same materials, particles, rigids, config and thread
  // count) and finalized continues bit for bit. loadState throws InputError
  // naming the file when the state belongs to another set-up.
  void saveState(io::BinaryWriter& w) const;
  void loadState(io::BinaryReader& r);

  // GPU back-end (cuda/device_bridge.cpp, docs/architecture.md "MPM on the
  // GPU"): after attachDevice each step() runs on `backend` (the CUDA plugin or
  // its host emulation) with the state kept there; syncFromDevice copies the
  // particles back (before outputs and checkpoints). kernel: NsMpmKernel.
  // deviceUnsupported: what this set-up uses that the GPU path lacks (empty: none).
  void attachDevice(const NsMpmBackend* backend, int kernel = 0);
  void syncFromDevice();
  bool onDevice() const { return device_ != nullptr; }
  std::vector<std::string> deviceUnsupported() const;

 private:
  StepReport deviceStep();
  void uploadToDevice();
  void dropDeviceState();  // loadState: the device copy is stale
  std::shared_ptr<DeviceRun> device_;
};

}  // namespace needlesim::mpm
