#pragma once
// Explicit 3D material point method (seed 000 eqs 1-4) with multi-field grid
// contact (eqs 14-21), CFL time step (eqs 25-27) and mass scaling (eq 28).
// Particles are an array of 256-byte records; the background grid is a dense
// box that is reset every step. Scatter is race-free on one shared grid: the
// points are sorted by grid block (4 base nodes wide along each axis), the
// blocks coloured in 2 x 2 x 2 parity, and the threads share out the blocks of
// one colour, which touch disjoint nodes. Interpretations: docs/models/mpm.md.
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

#include "needlesim/engines/mpm/grid_kernels.hpp"
#include "needlesim/engines/mpm/penalty_contact.hpp"
#include "needlesim/engines/mpm/surface_estimate.hpp"
#include "needlesim/io/binary_state.hpp"
#include "needlesim/materials/hyperelastic.hpp"

struct NsMpmBackend;  // cuda/mpm_device_abi.h

namespace needlesim::mpm {

class DeviceRun;  // cuda/device_bridge.cpp

namespace lanes {
template <int S>
struct Stencil4;  // support_lanes.hpp
}  // namespace lanes

using Vec3 = Eigen::Vector3d;

// The point of triangle (a, b, c) closest to p.
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
using Mat3 = Eigen::Matrix3d;

enum class Shape { Linear, BSpline2 };           // linear hat (the paper's) or quadratic B-spline
enum class Update { USL, MUSL };                 // update-stress-last, modified USL (momentum remap)
// Two-body gap rule: Centroid compares the centroid separation with that of
// two touching half-spaces seen from a node on the interface; Surface
// estimates each body's surface from its centroid at every node
// (surface_estimate.hpp).
enum class PairGapRule { Centroid, Surface };
// Normal contact of two deformable bodies: Velocity = the velocity-consistent
// impulse of eqs 15-18 (perfectly plastic at the contact nodes); Penalty = a
// penalty between overlapping material points of the two bodies that stores
// and returns the energy (penalty_contact.hpp).
// Density = a conservative penalty on the smoothed volume fraction of the
// other body (density_contact.hpp): central pair forces whose sum follows the
// smoothed surface normal, so point lattices sliding across each other do not
// interlock (not the default yet: ~2x the cost of the pair penalty in the
// two-block benchmark; docs/models/mpm.md).
enum class BodyContact { Velocity, Penalty, Density };
enum class FaceBC { Free, Fixed, Roller, NonReflecting };

// A tissue material as the solver uses it: the law plus the data of a fast path.
struct MpmMaterial {
  materials::Hyperelastic law;
  double density = 1000.0;  // kg/m^3, before mass scaling
  // Coulomb coefficient of the grid contact with a rigid body where this
  // material's point is nearest to it (eq 20); < 0: the rigid body's own.
  double rigidFriction = -1.0;
  static MpmMaterial fromSpec(const materials::MaterialSpec& spec);
};

// Cauchy stress of a material at F (fast closed forms for Fung-Demiray,
// neo-Hookean and St Venant-Kirchhoff; the materials library otherwise), the
// energy per reference volume W and the current dilatational wave speed (eq 27).
Mat3 evaluateStress(const MpmMaterial& m, const Mat3& F, double massScaling, double& W, double& wave);

// A rigid body with prescribed translation: an infinite plane or a needle
// (cylinder with a conical or bevelled tip). Normals are analytic.
struct RigidBody {
  enum class Kind { Plane, Needle } kind = Kind::Plane;
  enum class Tip { Conical, Bevel, Blunt } tip = Tip::Conical;
  Vec3 point = Vec3::Zero();    // plane: a point on it; needle: the tip point
  Vec3 normal = Vec3::UnitZ();  // plane: outward normal (out of the rigid half-space)
  Vec3 axis = Vec3::UnitX();    // needle: unit insertion direction (base -> tip)
  // needle, bevel tip: the side the bevel face looks to (needle::NeedleShape's
  // bevelSide): the heel on +bevelSide, the sharp point at -radius bevelSide.
  Vec3 bevelSide = Vec3::UnitY();
  double radius = 0.0;          // needle radius, m
  double tipAngle = 0.35;       // rad: cone half-angle / bevel angle to the axis
  Vec3 velocity = Vec3::Zero(); // m/s
  double friction = 0.0;        // Coulomb coefficient against the tissue (eq 20)
  bool surfaceContact = false;  // needle: CFEMP particle-to-surface contact (eqs 22-24) instead of grid contact
  double length = 0.04;         // needle: length tip to base, m (CFEMP surface)
  double elementSize = 0.0;     // CFEMP: d_e of the gap rule g < (d_e + d_p)/2 (eq 22), m
  // needle: the tissue parts along the needle's cut (needle_cut.cpp): no point
  // reaches a node across the strip of the plane through the axis normal to
  // bevelSide, as wide as the needle, that it has passed: the lips move apart.
  bool parting = false;
  double cutAhead = 0.0;        // parting: the cut reaches this far ahead of the tip plane (a pre-cut path), m
  // Signed distance (negative inside), the outward unit normal at the nearest
  // face, and which part is nearest (0 shaft or plane, 1 tip).
  double distance(const Vec3& x, Vec3* n, int* part) const;
  // Needle: the axis point level with the tip (`point`, or R off a bevel's sharp point).
  Vec3 axisPoint() const { return tip == Tip::Bevel ? Vec3(point + radius * bevelSide) : point; }
};

struct MpmConfig {
  double h = 1e-3;                 // grid spacing, m
  Vec3 origin = Vec3::Zero();      // position of node (0,0,0)
  std::array<int, 3> cells{{10, 10, 10}};
  Shape shape = Shape::BSpline2;
  Update update = Update::MUSL;
  int bodies = 1;                  // deformable velocity fields (1 or 2)
  double flip = 1.0;               // FLIP fraction of the particle velocity update (1 = pure FLIP, eq 4)
  double timeStepFactor = 0.4;     // k_t (eq 26)
  double massScaling = 1.0;        // factor on every particle mass (eq 28 discussion); dt grows with its root
  double fixedTimeStep = 0.0;      // > 0: use this step instead of eq 25-26 (still checked against it)
  double friction = 0.0;           // Coulomb coefficient between deformable bodies
  Vec3 gravity = Vec3::Zero();
  // Box whose faces carry the boundary conditions: faces x-, x+, y-, y+, z-, z+.
  Vec3 boxLo = Vec3::Zero(), boxHi = Vec3::Zero();
  std::array<FaceBC, 6> faces{{FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free, FaceBC::Free}};
  // Grid nodes (i, j, k) held fixed besides the faces' (an imported geometry's supported side).
  std::vector<std::array<int, 3>> heldNodes;
  double contactGap = -1.0;        // eq 22 gap for rigid contact, m (< 0: half the particle spacing)
  PairGapRule pairGapRule = PairGapRule::Surface;
  double pairGapFactor = 1.0;      // Centroid rule: scales the centroid-separation gap of two deformable bodies
  double pairGapTolerance = 0.0;   // Surface rule: contact when the estimated surfaces are closer than this, cells
  BodyContact bodyContact = BodyContact::Penalty;  // two deformable bodies (the rigid and CFEMP contacts are unaffected)
  double penaltyFactor = 0.2;      // Penalty, Density: kappa, pair stiffness kappa M d_p (M: largest P-wave modulus)
  double penaltyStepFactor = 0.15; // Penalty, Density: while in contact dt <= this / omega, omega^2 = k / m_r of a pair (0: off)
  int threads = 0;                 // 0 = OpenMP default
  bool fbar = false;               // anti-locking: stress at F-bar with the cell-averaged det F
};

// Totals of one step, for reporting.
struct StepReport {
  double dt = 0.0;
  double kinetic = 0.0;   // J (scaled masses)
  double internal = 0.0;  // J
  double maxSpeed = 0.0;  // max (c_p + |v_p|), m/s
  double contact = 0.0;      // J, energy stored in the penalty contact of two bodies (end-of-step positions)
  double penetration = 0.0;  // m, largest overlap (d_p + d_q)/2 - |x_p - x_q| of two points of different bodies
  double frictionWork = 0.0; // J, work of the penalty contact's friction forces this step (>= 0, dissipated)
};

// Contact force the tissue exerts on one rigid body in the last step.
struct RigidForce {
  Vec3 total = Vec3::Zero(), tip = Vec3::Zero(), shaft = Vec3::Zero();
  int contactNodes = 0;
};

// The particle lattice addBlock fills a box with: n[d] points along each axis, spacing sp[d]
// (dp rounded so that whole points fit), point (i, j, k) at lo + (i + 1/2, j + 1/2, k + 1/2) sp.
struct Lattice {
  Vec3 lo = Vec3::Zero();
  std::array<int, 3> n{{1, 1, 1}};
  Vec3 sp = Vec3::Ones();
  Lattice(const Vec3& lo, const Vec3& hi, double dp);
  std::size_t size() const { return static_cast<std::size_t>(n[0]) * n[1] * n[2]; }
  std::size_t index(int i, int j, int k) const { return (static_cast<std::size_t>(i) * n[1] + j) * n[2] + k; }
  Vec3 point(int i, int j, int k) const { return lo + Vec3((i + 0.5) * sp[0], (j + 0.5) * sp[1], (k + 0.5) * sp[2]); }
};

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
  Mat3 defGrad(std::size_t p) const;
  Mat3 cauchy(std::size_t p) const;
  double mass(std::size_t p) const { return P_[p].mass; }           // scaled
  double volume0(std::size_t p) const { return P_[p].vol0; }
  int body(std::size_t p) const { return body_[p]; }
  int material(std::size_t p) const { return mat_[p]; }
  double particleSpacing() const { return dp_; }
  void setVelocity(std::size_t p, const Vec3& v) { P_[p].v[0] = v.x(); P_[p].v[1] = v.y(); P_[p].v[2] = v.z(); }
  void setPosition(std::size_t p, const Vec3& x) {  // tests (contactForces); the next step sorts the points again
    P_[p].x[0] = x.x(); P_[p].x[1] = x.y(); P_[p].x[2] = x.z();
    planned_ = false;
  }
  const MpmConfig& config() const { return cfg_; }
  int threads() const { return nthreads_; }
  // The block colouring of the scatters for a team of `team` threads
  // (planScatter; one thread: creation order, one pass): colours with points
  // (a barrier between two), blocks with points, threads that get points, and
  // the imbalance, the sum over the colours of the largest thread's share over
  // the mean share (1: even; the scatters' speed-up is at most team / imbalance),
  // and the sorts by block since finalize.
  struct ScatterPlan {
    int colours = 1;
    std::size_t blocks = 0;
    int busyThreads = 1;
    double imbalance = 1.0;
    long long sorts = 0;
  };
  ScatterPlan scatterPlan(int team) const;
  int scatterThreads() const { return scatterThreads_; }  // threads that scattered points in the last p2g
  // Wall time and process CPU time (all threads) of each phase of step(),
  // summed over the steps since finalize or the last resetPhaseTimes (s);
  // bench_mpm --phases prints them per step.
  enum Phase { kSort, kZeroGrid, kScatter, kPenalty, kGridPlan, kGridUpdate, kRigidSums, kContact, kRemap,
               kRemapUpdate, kG2P, kPhases };
  static const char* phaseName(int phase);
  const std::array<double, kPhases>& phaseTimes() const { return phaseTimes_; }
  const std::array<double, kPhases>& phaseCpuTimes() const { return phaseCpu_; }
  // Of the particle passes (kScatter, kRemap, kG2P): the time each thread
  // worked in them, barrier waits left out (s, summed as phaseTimes); the
  // largest over the mean is the imbalance of the work, not of the points.
  std::vector<double> threadBusy(Phase phase) const;
  void resetPhaseTimes() {
    phaseTimes_.fill(0.0);
    phaseCpu_.fill(0.0);
    busy_.assign(busy_.size(), 0.0);
  }
  // Points whose support the needle's cut crosses this step (planCut; tests).
  std::size_t cutPoints() const;
  // Tests: the two-body contact forces (pair penalty or density law, without
  // friction) on every point at the current positions, and the contact energy
  // there (J); the solver's state is unchanged (penalty_contact.cpp).
  double contactForces(std::vector<Vec3>& force);

 private:
  void checkIds(int material, int body) const;
  void pushParticle(const Vec3& x, const Vec3& v, double mass, double volume, int material, int body);
  void setUpPairContact();   // finalize
  void setUpBoundaries();    // finalize
  void checkInitialState();  // finalize
  template <int S, bool Grad> void p2g();
  struct NeedleAxis;
  std::array<NeedleAxis, 8> needleAxes(double gapReach) const;  // p2g
  template <int S, bool Grad>
  void scatterPoint(std::size_t p, const lanes::Stencil4<S>& st, const double* xp, bool needG, bool centroid,
                    double* __restrict rec, double* __restrict grad, std::size_t n1, std::size_t n2);  // p2g
  template <int S> void g2pRemap();
  template <int S> void surfaceContact(bool first);
  void findSurfacePairs(std::size_t r);  // surfaceContact
  void buildSurface(std::size_t r);
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
  void densityForces();           // density_contact.cpp
  void resetDensityScratch();                                                                   // densityForces
  int densityNearCells(std::size_t c0, std::uint32_t* lo, std::uint32_t* hi, const double** bb) const;  // densityForces
  void densitySweepCell(std::size_t c0, std::size_t tid, double* racc, std::size_t from);       // densityForces
  void densityLawAt(std::size_t s, std::size_t tid, double dt0, std::atomic<std::size_t>& passed);  // densityForces
  void densityFrictionInputs(std::size_t tid);                                                  // densityForces
  void densityPairForces(std::size_t tid, bool friction, double mu, double dt);                 // densityForces
  void densityEnergyAfterStep();  // density_contact.cpp
  bool surfaceNormal(const double* x, double* m) const;  // density_contact.cpp
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
  void scatterCutPoint(std::size_t p, bool needG, bool centroid);                  // p2g
  void remapCutPoint(std::size_t p, double flip);                                  // g2pRemap
  void gatherCutPoint(std::size_t p, std::size_t off, bool usl, double* an, double* ao, double* L) const;  // g2pFinal
  GridSums cutGridSums(std::size_t p, std::size_t off, bool usl) const;           // g2pFinal
  int cutSurfaceWeights(std::size_t p, std::size_t* node, double* w) const;       // surfaceContact
  bool wallLipNormal(std::size_t r, const Vec3& x, Vec3& n) const;                // rigidContactAt, findSurfacePairs
  void zeroGrid(int t, int T);
  void planScatter();
  void sortByBlock();  // planScatter
  std::pair<std::size_t, std::size_t> colourShare(int t, int T, int colour) const;
  void blockBounds(std::size_t listed, int* lo, int* hi) const;  // g2pFinal
  bool scatterPlanValid(const std::vector<std::uint32_t>& starts, const std::vector<std::uint32_t>& ids,
                        const std::vector<std::uint32_t>& colours, const int* origin, const int* blocks,
                        bool planned) const;  // loadState
  bool colourHasPoints(int c) const {
    return nthreads_ == 1 ? c == 0 : colourStart_[static_cast<std::size_t>(c)] != colourStart_[static_cast<std::size_t>(c) + 1];
  }
  int lastScatterColour() const {
    int last = 0;
    for (int c = 1; c < 8; ++c)
      if (colourHasPoints(c)) last = c;
    return last;
  }
  void stress(std::size_t p, const Mat3& F, double& energy, double& wave);
  void fbarStress(double& ei, double& vmax);
  void markNearBodies();
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
  // and the mass-weighted position (3), pad (2) in a second array of 8
  // doubles per node per body, written only by the points near the other
  // body (p2g), so the scatter of all other points touches half the memory.
  struct Buf {
    grid::LineVector<double> rec;   // nr_ per node per body (64-byte aligned records)
    grid::LineVector<double> grad;  // two bodies: 8 per node per body (grid::kG; grid::kX velocity contact only)
    std::vector<double> gmin;      // per node per rigid
    std::vector<std::uint8_t> gmat;  // per node per rigid: material of the point of the smallest gap (materialFriction_)
  };
  std::vector<Buf> buf_;                // one shared grid (buf_[0])
  // Race-free scatter (3D block colouring, sortByBlock): the grid is cut,
  // from the points' lowest base node on (so that few blocks are partly
  // filled), into blocks of kBlock base nodes along each axis, block (bi, bj, bk) of
  // colour (bi & 1) | (bj & 1) << 1 | (bk & 1) << 2; order_ visits the points
  // colour by colour, block by block (creation order within a block); listed
  // block b is order_[blockStart_[b], blockStart_[b + 1]), of grid block
  // blockId_[b]; colour c is listed blocks [colourStart_[c], colourStart_[c + 1]).
  // A point whose base node leaves its block by more than one node (g2pFinal)
  // asks for a re-sort before the next scatter (planned_ false).
  static constexpr int kBlock = 4;
  std::vector<std::uint32_t> sortPointsByKey(const std::vector<std::uint32_t>& key, std::size_t nkeys);
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> blockStart_, blockId_;
  std::array<std::uint32_t, 9> colourStart_{};
  int blockOrigin_[3] = {0, 0, 0};      // base node where block 0 starts along each axis (the points' lowest)
  int blocks_[3] = {0, 0, 0};           // blocks from there to the grid's end along each axis
  bool planned_ = false;
  int scatterThreads_ = 1;
  long long sorts_ = 0;
  std::array<double, kPhases> phaseTimes_{}, phaseCpu_{};
  std::vector<double> busy_;  // [phase][thread]: threadBusy
  void addBusy(Phase phase, int t, double seconds);
  void addPhase(Phase phase, double wall0, double cpu0, double wall1, double cpu1) {
    phaseTimes_[phase] += wall1 - wall0;
    phaseCpu_[phase] += cpu1 - cpu0;
  }
  bool gridClean_ = false;              // the records are all zero (remapUpdate cleared them)
  int nr_ = 8;
  grid::LineVector<double> vel_;        // per node per body: v_new (3), pad, v_old (3), pad
  std::vector<std::uint8_t> fixMask_;   // per node: bits 0-2 fixed velocity components
  std::vector<double> dashpot_;         // per node: 3 viscous coefficients (non-reflecting), kg/s
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
  double pairGap_ = 0.0;
  std::optional<SurfaceFromCentroid> surfaceEst_;  // Surface gap rule
  std::optional<PairPenalty> penalty_;  // two bodies, BodyContact::Penalty (penalty_contact.cpp)
  Vec3 nodePosition(std::size_t I) const;
  // Two bodies (markNearBodies): per (i, j) row, per body nearW_ words, bit k
  // of cell (i, j, k). occ_: a point of the body in the cell (set by g2pFinal
  // at the new positions while occFresh_, else by a pass over the points);
  // near1_ / near_: occupied cells dilated by 1 / 3 cells.
  std::vector<std::uint64_t> occ_, near1_, near_, nearTmp_;
  std::size_t nearW_ = 1;
  bool occFresh_ = false;
  // Two bodies: per point, its cell index (i n1 + j) n2 + k when the other
  // body occupies one of the 27 cells around it (near1_, set by p2g: the
  // penalty contact's candidates), else kNotNear.
  static constexpr std::uint32_t kNotNear = ~std::uint32_t{0};
  std::vector<std::uint32_t> nearCell_;
  std::vector<std::uint32_t> cellOf_;   // F-bar: cell of each particle
  std::vector<double> cellJ_;           // F-bar: per cell sum V0 J, sum V0
  // CFEMP (eqs 22-24): the needle surface triangulated in its own frame (tip at
  // the origin, axis x, sharp point at -R y) with a uniform bucket grid.
  struct Surface {
    std::vector<Vec3> a, b, c, n;       // triangle corners and outward normals
    std::vector<std::uint8_t> tip;      // 1: tip face (force split)
    Vec3 lo = Vec3::Zero();
    double cell = 0.0, reach = 0.0;
    int dim[3] = {0, 0, 0};
    std::vector<int> start, items;      // triangles per bucket (CSR)
  };
  std::vector<Surface> surf_;           // per rigid (empty for grid contact)
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
