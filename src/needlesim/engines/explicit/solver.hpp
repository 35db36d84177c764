#pragma once
// Total Lagrangian explicit dynamics (Belytschko, Liu, Moran & Elkhodary,
// "Nonlinear Finite Elements for Continua and Structures", 2nd ed., box 6.1):
//   central difference with lumped mass, internal forces f_a = V0 P grad0 N_a,
//   P = F S (first Piola-Kirchhoff), S from the materials library.
// Elements: quad4 (plane strain) and hex8 with one-point (reduced) integration
// and Flanagan-Belytschko (1981) hourglass stiffness on the displacement
// (orthogonal to all linear fields, so patch tests and rigid motions give no
// hourglass force); tri3 and tet4 constant-strain elements. One-point
// integration evaluates J once per element, which is the mean-dilatation
// treatment of near incompressibility (Nagtegaal, Parks & Rice 1974; the
// hourglass stiffness is scaled by the shear modulus only so the bulk modulus
// never stiffens bending). Bulk viscosity as ABAQUS/Explicit (linear b1 and
// quadratic b2 terms). Element-wise stable step from the current mesh:
//   dt_e = 2 / (c_d sqrt(n_a sum_a |grad N_a|^2)) (sqrt(1 + xi^2) - xi)
// (Flanagan-Belytschko's bound on the element's highest frequency; seed 000
// eqs 25-27 use the same CFL idea with a characteristic length), with
// c_d = sqrt((K + 4/3 mu)/rho) and xi the bulk-viscosity damping ratio.
// Mass scaling by a factor or to a target step (seed 000 eq 28).
// Contact: rigid needle (needle/surface_mesh.hpp) and rigid planes, penalty
// node-to-surface with Coulomb friction (elastic stick predictor, return map).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/cohesive_wedge.hpp"
#include "needlesim/engines/explicit/mesh.hpp"
#include "needlesim/engines/explicit/needle_motion.hpp"
#include "needlesim/materials/hyperelastic.hpp"
#include "needlesim/materials/viscoelastic.hpp"
#include "needlesim/needle/surface_mesh.hpp"

namespace needlesim::explicit_fe {

struct Material {
  materials::Hyperelastic law;
  materials::Prony prony;  // empty = elastic
  double density = 1000.0;  // kg/m^3
  static Material fromSpec(const materials::MaterialSpec& spec);
};

struct SolverOptions {
  double massScaling = 1.0;      // factor on every element's density (>= 1)
  double targetTimeStep = 0.0;   // s; > 0: scale the mass of elements whose dt is smaller
  double cfl = 0.9;              // fraction of the stable step used
  double maxTimeStep = 0.0;      // s; > 0 caps the step
  double bulkViscosityLinear = 0.06;     // b1 (ABAQUS default)
  double bulkViscosityQuadratic = 1.2;   // b2 (ABAQUS default)
  double hourglass = 1.0;        // hourglass stiffness; 1 = exact pure bending of a rectangular element
  double damping = 0.0;          // 1/s, mass-proportional (dynamic relaxation; 0 = none)
  // Normal contact stiffness k = penalty m_a / (cfl dt_stable)^2 (contact_normal.cpp): the normal
  // force is evaluated at the end of the step (implicit, node-local), so any penalty is stable;
  // default 10 keeps the penetration ~1/10 of what the element's own stiffness would give.
  double contactPenalty = 10.0;
  double stickPenalty = 0.2;     // tangential (friction stick) stiffness, fraction of m/dt^2 (< 1, explicit)
  double lipPenalty = 0.3;       // explicit normal penalty on cohesive seam lips when contactPenalty > 1
  // true: k from the first contact evaluation's stable step, then kept: a conservative penalty (with k
  // following dt the stored 1/2 k g^2 grows without work as elements distort; docs/models/cohesive.md)
  bool fixedContactStiffness = false;
  double penetrationTolerance = 0.0;  // m; 0 = half the smallest element size
  double hourglassStrainLimit = 2.0;  // stop when an element's hourglass (zig-zag) strain exceeds this
  double minTimeStepRatio = 1e-3;     // stop when dt falls below this fraction of the initial dt
  // tri3/tet4: average nodal pressure (Bonet & Burton 1998; nodal_pressure.cpp) against volumetric locking
  bool nodalPressure = true;
};

struct Energies {
  double kinetic = 0.0;       // J (2D: J per metre of thickness), at the half step
  double kineticMid = 0.0;    // at the start of the last step, from the mean of the half-step velocities
  double internal = 0.0;      // work of internal forces (elastic + hourglass + viscous)
  double strain = 0.0;        // stored elastic energy sum V0 W(F) (elastic part of the law)
  double hourglass = 0.0;     // stored hourglass energy
  double externalWork = 0.0;  // loads and reactions at prescribed dofs
  double contactWork = 0.0;   // work of contact forces on the body (negative = dissipated)
  double dampingWork = 0.0;   // work of mass-proportional damping (negative)
  double cohesiveWork = 0.0;  // work done on the cohesive interface (= stored + dissipated)
  double cohesiveStored = 0.0, cohesiveDissipated = 0.0;  // its split (cohesive.hpp)
  double kinetic0 = 0.0;
  // Needle contact split (docs/models/cohesive.md "Energy balance"): work the moving needle does
  // (its reaction times its velocity), the part of the contact work on the body that came from the
  // needle, Coulomb friction dissipation (friction force times slip, >= 0) and the penalty energy
  // 1/2 k depth^2 stored in the needle contact now.
  double needleWork = 0.0, needleContactWork = 0.0, frictionDissipation = 0.0, penaltyEnergy = 0.0;
  // ETOTAL in ABAQUS terms: kinetic + internal - external - contact - damping, minus its start value.
  double balance() const {
    return kinetic - kinetic0 + internal + cohesiveWork - externalWork - contactWork - dampingWork;
  }
  // The whole-insertion balance: needle work = kinetic + internal (strain, hourglass, viscous) +
  // cohesive (stored + dissipated) + friction dissipation + penalty energy (+ loads, damping, planes).
  // Not round-off exact: the penalty energy is a state function only up to the step's change of k.
  double balanceWithNeedle() const {
    return kinetic - kinetic0 + internal + cohesiveWork + frictionDissipation + penaltyEnergy - needleWork -
           externalWork - dampingWork - (contactWork - needleContactWork);
  }
};

struct RigidPlane {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitY();  // outward: the body lies on this side
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
  double friction = 0.0;
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // reaction on the plane (from the body), applied in the last step
};

class NeedlePath;  // path_needle.hpp

struct RigidNeedle {
  needle::NeedleShape shape;
  needle::NeedlePose pose;
  double velocity = 0.0;         // m/s along pose.axis
  double spinRate = 0.0;         // rad/s about pose.axis (needle_motion.hpp; 3D)
  double frictionWall = 0.0;     // Coulomb coefficient on the walls (seed 001: 0.3)
  double frictionTip = 0.0;      // on the tip surface (seed 001: frictionless)
  std::vector<double> frictionWallNode;  // per tissue node: its layer's or inclusion's (empty = frictionWall)
  double wallFriction(int node) const { return frictionWallNode.empty() ? frictionWall : frictionWallNode[node]; }
  // loads applied in the last step (the normal part evaluated at its end, contact_normal.cpp)
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // reaction on the needle (from the tissue)
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();  // about the base centre
  Eigen::Vector3d tipForce = Eigen::Vector3d::Zero();  // part of `force` acting on the tip surface
  double normalForce = 0.0;      // sum of normal force magnitudes
  int nodesInContact = 0;
  double maxPenetration = 0.0;
  // Follow-the-leader along a 2D path (path_needle.hpp); null = the straight needle of `pose`.
  std::shared_ptr<const NeedlePath> path;
  double station = 0.0;     // arc length of the tip along the path
  int pathSide = 1;         // bevelSide = pathSide x the path normal
  double driveForce = 0.0;  // path: reaction along the local path tangents (the work-conjugate force)
};

class ExplicitSolver {
 public:
  ExplicitSolver(Mesh mesh, std::vector<Material> materials, SolverOptions options = {});

  // Boundary conditions: a group of dofs moving with one prescribed velocity (0 = fixed).
  int addGroup();
  void addDof(int group, int node, int component);
  void setGroupVelocity(int group, double v) { groupVelocity_[group] = v; }
  double groupReaction(int group) const { return groupReaction_[group]; }  // force the support applies
  void setExternalForce(int node, int component, double f) { fext_[node * dim_ + component] = f; }

  // Tie two coincident nodes (a pre-cut seam) until the needle's leading point
  // comes within `releaseDistance` of them along the axis (node release).
  void addTie(int a, int b);
  // Node-release slit through the needle's leading point (3D): its lips (nodes with a contact side) meet
  // the needle through the lip wedge of cohesive_wedge.hpp (LipSeam::ThroughPoint), each pushed across the
  // slit to the needle's outline on its own side, instead of through queryNeedle's nearest exit.
  void setWedgeLips(bool on) { wedgeLips_ = on; }
  // Which lip of a cut through the bevel's sharp point a node lies on (+1 the bevel
  // side, -1 the wall side; needle::queryNeedle's `side`): set on seam nodes.
  void setContactSide(int node, int side);
  // Cylindrical cohesive sleeve of radius r (mesh_sleeve.hpp): the seam lips (setContactSide -1 core,
  // +1 outer) meet the annular wedge of a hollow bevel needle (cohesive_sleeve.hpp) instead of lipWedge.
  void setSleeveRadius(double r) { sleeveRadius_ = r; }
  int activeTies() const;

  // Cohesive zone on seam pairs (cohesive.hpp): forces join the internal forces,
  // the stable step accounts for the pair springs. 2D lines or 3D quadrilaterals.
  void setCohesive(CohesiveInterface c);
  CohesiveInterface* cohesive() { return coh_.empty() ? nullptr : &coh_.front(); }
  const CohesiveInterface* cohesive() const { return coh_.empty() ? nullptr : &coh_.front(); }

  // Normal contact of `node` with an analytic rigid body outside the solver (tests: rigid_sphere.hpp),
  // for the next step: penetration `depth` along `normal` (out of the body), body velocity `vb`,
  // stiffness contactStiffness(node). Call between steps; the force applied in the step is
  // externalContactForce() after it.
  void addNormalContact(int node, const Eigen::Vector3d& normal, double depth, const Eigen::Vector3d& vb);
  double contactStiffness(int node) const;
  Eigen::Vector3d externalContactForce() const { return extContactForceLast_; }  // on the body, last step
  // Normal contact force per node applied in the last step (0 = no contact), N (2D: N/m).
  double nodeContactForce(int node) const { return contactFnApplied_.empty() ? 0.0 : contactFnApplied_[node]; }
  // Its direction (out of the rigid body) at the current configuration; zero when not in contact.
  Eigen::Vector3d nodeContactNormal(int node) const {
    if (contactBody_.empty() || contactBody_[node] < 0) return Eigen::Vector3d::Zero();
    const double* c = &contactNrm_[static_cast<std::size_t>(node) * 3];
    return Eigen::Vector3d(c[0], c[1], c[2]);
  }

  // sum k (n.e)^2 over the nodes in needle contact in the last step: the lateral penalty stiffness
  // along e the deformable needle's coupling relaxes against (deformable_needle.cpp)
  double needleLateralStiffness(const Eigen::Vector3d& e) const;

  int addPlane(const RigidPlane& plane);
  RigidPlane& plane(int i) { return planes_[i]; }
  void setNeedle(const RigidNeedle& n);
  RigidNeedle* needle() { return hasNeedle_ ? &needle_ : nullptr; }

  // One central-difference step; throws SolverError with cause, place, time and remedy.
  void step();
  // Steps until time t (the last step is shortened to land on t).
  void advanceTo(double t);

  double time() const { return time_; }
  double timeStep() const { return dt_; }
  double stableTimeStep() const { return dtStable_; }
  long steps() const { return steps_; }
  const Energies& energies() const { return en_; }
  const Mesh& mesh() const { return mesh_; }
  int dim() const { return dim_; }
  const std::vector<double>& displacement() const { return u_; }
  const std::vector<double>& velocity() const { return vHalf_; }
  std::vector<double>& velocityMutable() { return vHalf_; }  // initial conditions
  const std::vector<double>& nodalMass() const { return mass_; }
  const std::vector<double>& internalForce() const { return fint_; }
  // Sets the displacement (initial conditions, patch tests) and recomputes the forces there.
  void setDisplacement(const std::vector<double>& u);
  double totalMass() const;
  double physicalMass() const { return physicalMass_; }
  double minElementSize() const { return minSize_; }
  long elementUpdates() const { return elementUpdates_; }

  // Output: per element Cauchy stress (6 Voigt: xx yy zz xy yz xz), von Mises,
  // log strain (6) and J; per node current coordinates (dim).
  void cellFields(std::vector<double>& cauchy, std::vector<double>& mises, std::vector<double>& logStrain,
                  std::vector<double>& J) const;
  Eigen::Matrix3d deformationGradient(int e) const;

 private:
  // set-up steps of the constructor
  void validateInput();
  void allocateElementData();
  void referenceGeometry(int e);
  void hourglassVectors(int e);
  void elementStiffnessAndMass(int e);
  void allocatePronyStates();
  void buildNodeSlots();
  void lumpedMassAndNodeData();
  template <int NPE, int DIM>
  void internalForces(double dtStep);
  [[noreturn]] void failInverted(int bad) const;
  // steps of step()
  void startFirstStep();
  void tieForces(double alpha);
  void checkHourglassing() const;
  // internalForces for this mesh's element type.
  void elementForces(double dtStep);
  void contactForces(double dtStep);
  // the step's contact penalties: step dtStep, stable step dtPen of the normal penalty
  // k = contactPenalty m / dtPen^2, stick spring k = stick m / dtPen^2
  struct ContactStep {
    double dtStep, dtPen, stick;
  };
  // steps of contactForces: the rigid planes, the needle, one tissue node in needle contact
  void planeContactForces(const ContactStep& cs);
  void needleContactForces(const ContactStep& cs);
  struct NeedleNodeForce {
    Eigen::Vector3d force;  // on the tissue node: normal plus friction
    double normal, energy;  // penalty normal force and energy
  };
  NeedleNodeForce needleNodeForce(int n, const Eigen::Vector3d& v, const Eigen::Vector3d& vb,
                                  const needle::NeedlePose& pose, const needle::NeedleHit& hit, double wedgeAxial,
                                  const ContactStep& cs);
  // current position and half-step velocity of node n (2D: z = 0)
  void nodeState(int n, Eigen::Vector3d& x, Eigen::Vector3d& v) const {
    x.setZero(), v.setZero();
    for (int i = 0; i < dim_; ++i) {
      x[i] = mesh_.X[static_cast<std::size_t>(n) * dim_ + i] + u_[static_cast<std::size_t>(n) * dim_ + i];
      v[i] = vHalf_[static_cast<std::size_t>(n) * dim_ + i];
    }
  }
  double contactTimeStep();
  needle::NeedleHit needleHit(int n, const Eigen::Vector3d& x, const needle::NeedlePose& pose, double& wedgeAxial) const;
  double needleContactStiffness(int n, double dtPen);
  [[noreturn]] void failNeedlePenetration(double maxPen) const;
  // needle contact stiffness of a node, kept over its contact episode (solver.cpp)
  double episodeStiffness(int n, double k0, double kMax);
  static constexpr double kLipPenaltyMax = 0.6;  // explicit lip penalty cap, m/(cfl dt_stable)^2
  // Normal contact forces evaluated at the end of the step (contact_normal.cpp).
  void recordNormalContact(int node, int body, const Eigen::Vector3d& normal, double k, double depth,
                           const Eigen::Vector3d& vb, double mu = 0.0);
  void normalContactCorrection(double dt, double dtAvg);
  bool lessStartOverlap(int node, const Eigen::Vector3d& xRef, needle::NeedleHit& hit) const;
  // The seam whose lips the needle wedges: the 2D cut line, the 3D node-release slit through the leading
  // point (setWedgeLips) or the 3D cohesive seam through the axis.
  LipSeam lipSeam() const {
    if (dim_ == 2) return LipSeam::Planar;
    return wedgeLips_ && cohPairOf_.empty() ? LipSeam::ThroughPoint : LipSeam::ThroughAxis;
  }
  void gatherForces();
  // tri3/tet4 average nodal pressure: replaces each element's pressure by the mean of its nodes'
  // volume-averaged pressures (nodal_pressure.cpp)
  // Returns the change of the stored energy: nodal minus element volumetric energy p^2 / 2K.
  double nodalPressureCorrection();
  void computeStableStep();
  [[noreturn]] void fail(const std::string& cause, const std::string& where, const std::string& remedy) const;
  std::string elementWhere(int e) const;

  Mesh mesh_;
  std::vector<Material> mats_;
  SolverOptions opt_;
  int dim_, npe_, nel_, nnode_, nhg_;
  // element data, structure of arrays
  std::vector<double> grad0_;   // nel * npe * dim: dN/dX at the centroid
  std::vector<double> gamma_;   // nel * nhg * npe: hourglass shape vectors
  std::vector<double> vol0_;    // reference volume (2D: area x 1 m)
  std::vector<double> rho_;     // density incl. mass scaling
  std::vector<double> hgStiff_; // hourglass stiffness
  std::vector<int> mat_;
  std::vector<double> fe_;      // nel * npe * dim element forces
  std::vector<double> dtElem_;
  std::vector<double> wElem_, hgElem_, hgStrain_;
  std::vector<int> failElem_;   // per element failure code (0 ok)
  std::vector<double> spk2_;    // nel * 6: second Piola-Kirchhoff stress (Voigt) of the last step
  std::vector<double> anpP_, anpB_, anpNode_, anpDp_;  // nodal pressure: element p, V0 J F^-T grad0 N, nodal p
  std::vector<materials::PronyState<Eigen::Matrix<double, 6, 1>>> prony_;
  std::vector<double> matWaveModulus_, matShear_, matBulk_;
  // node data
  std::vector<int> nodeStart_, nodeSlots_;  // CSR node -> element slots (e*npe + a)
  std::vector<double> mass_, u_, vHalf_, fint_, fext_, fcon_, react_;
  std::vector<double> vBar_;
  std::vector<int> dofGroup_;   // -1 free
  std::vector<double> groupVelocity_, groupReaction_;
  // contact
  std::vector<RigidPlane> planes_;
  std::vector<std::vector<double>> planeFt_;
  RigidNeedle needle_;
  bool hasNeedle_ = false;
  std::vector<double> needleFt_;
  std::vector<double> fconNeedle_, fconFriction_;  // per dof: needle contact force on the body, its friction part
  std::vector<double> needleK_;  // per node: needle contact stiffness of the current contact episode (0 = none)
  std::vector<signed char> contactSide_;  // per node, empty = none
  double penetrationTol_ = 0.0;
  double dtPenFixed_ = 0.0;  // stable step of the first contact evaluation (fixedContactStiffness)
  // normal contact per node (contact_normal.cpp): body -1 none, 0 needle, 1 external, 2 + p plane p
  std::vector<int> contactBody_;
  std::vector<double> contactK_, contactDepth_, contactNrm_, contactVb_, contactMu_;
  std::vector<double> contactFnApplied_;  // normal force applied in the last step
  std::vector<double> contactWedge_;  // needle: axial reaction per unit normal force of a wedged seam lip
  std::vector<char> contactTip_;      // needle: contact on the tip surface
  struct NeedleLoads {
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero(), tip = Eigen::Vector3d::Zero();
    double normal = 0.0;
    double drive = 0.0;  // path needle: reaction along the local tangents
  } needleStage_;
  std::vector<double> contactAxis_;  // path needle: local axis per node in needle contact (3 per node)
  std::vector<Eigen::Vector3d> planeStage_;
  Eigen::Vector3d extContactForce_ = Eigen::Vector3d::Zero(), extContactForceLast_ = Eigen::Vector3d::Zero();
  // seam ties
  std::vector<int> tieA_, tieB_;
  std::vector<char> tieOn_;
  bool wedgeLips_ = false;       // setWedgeLips
  needle::NeedlePose pose0_;     // the needle's pose at setNeedle (lessStartOverlap)
  std::vector<double> ftie_;
  double releaseDistance_ = 0.0;
  double sleeveRadius_ = 0.0;  // > 0: the cohesive seam is a cylindrical sleeve (cohesive_sleeve.hpp)
  // cohesive zone (0 or 1 interface)
  std::vector<CohesiveInterface> coh_;
  std::vector<double> fcoh_;
  std::vector<int> cohPairOf_;  // per node: its cohesive pair, -1 none
  double cohOmega2_ = 0.0;
  void cohesiveForces();
  // state
  double time_ = 0.0, dt_ = 0.0, dtPrev_ = 0.0, dtStable_ = 0.0, dtInitial_ = 0.0;
  double physicalMass_ = 0.0, minSize_ = 0.0;
  long steps_ = 0, elementUpdates_ = 0;
  Energies en_;
};

}  // namespace needlesim::explicit_fe
