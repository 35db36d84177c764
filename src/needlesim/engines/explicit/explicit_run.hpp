#pragma once
// One run of the explicit engine (docs/models/explicit.md) in named steps:
//   set-up (explicit_setup.cpp): the tissue mesh with one region per layer and per inclusion,
//     the pre-cut seam or cohesive zone, the solver, the fixed distal face and the needle in the
//     shared insertion frame (needle/insertion_frame.hpp);
//   step (explicit_engine.cpp): pose the needle from the motion profile, advance the solver;
//   record and finish (explicit_outputs.cpp): forces.csv (results/forces_table.hpp), energy.csv,
//     contact.csv, seam.csv, inclusions.csv, markers.csv, fields, and the summary results.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/explicit/cohesive.hpp"
#include "needlesim/engines/explicit/contact_output.hpp"
#include "needlesim/engines/explicit/deformable_needle.hpp"
#include "needlesim/engines/explicit/mesh_sleeve.hpp"
#include "needlesim/engines/explicit/path_from_scenario.hpp"
#include "needlesim/engines/explicit/solver.hpp"
#include "needlesim/engines/realtime/markers.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/io/table.hpp"
#include "needlesim/needle/insertion_frame.hpp"
#include "needlesim/results/forces_table.hpp"
#include "needlesim/results/inclusion_motion.hpp"

namespace needlesim::io {
class FieldSeries;
}

namespace needlesim::explicit_fe {

class ExplicitRun {
 public:
  ExplicitRun(const Scenario& sc, ResultSink& sink);
  // The time loop with its records; writes the results also when the solver stops (then rethrows).
  void run(const RunOptions& options);
  // How the run steps (engines/step_guard.hpp): the initial stable step against the smallest element.
  StepPlan stepPlan() const;

 private:
  // set-up (explicit_setup.cpp)
  void checkInput() const;
  void chooseSeam();
  void buildMesh();
  void buildBlock();
  void cutSeam();
  void requireNodesOnSlit() const;
  void assignRegions();
  void checkInclusionResolution();
  std::vector<Material> regionMaterials() const;
  SolverOptions solverOptions() const;
  void setupSeam();
  void requireSeamOnPlane() const;
  void setupCohesive();
  CohesiveLaw cohesiveLawAt(const Eigen::Vector3d& x) const;
  void fixDistalFace();
  void setupNeedle();
  std::vector<double> wallFrictionPerNode() const;
  // step (explicit_engine.cpp)
  void poseNeedle(double t, double dt);
  void requireContact() const;
  // record and finish (explicit_outputs.cpp)
  void createOutputs();
  void record();
  void recordEnergies(double depth);
  void recordSeam(double depth);
  void recordInclusions(double depth);
  void placeMarkers();
  void writeFields();
  void finish(const std::string& status);
  void reportForces();
  void reportEnergies();
  void warnOnEnergyBalance(double body);  // a warning when the energy balance is far from zero
  void warnOnNeedleBalance(double needle);  // a warning when the needle work does not balance
  void reportCohesive();
  void reportNotes(const std::string& status);
  double crackedLength() const;

  const Scenario& sc_;
  const ExplicitModelSpec& ex_;
  ResultSink& sink_;
  needle::InsertionFrame frame_;
  needle::NeedleShape shape_;
  MotionProfile motion_;
  int dim_ = 2;
  Eigen::Vector3d bevelSide_ = Eigen::Vector3d::UnitY();  // at the start (2D: +-lateral)
  // seam: node release (pre_cut) or cohesive, through the bevel's sharp point (or the axis)
  bool seamOn_ = false, sleeve_ = false, cohesive_ = false;
  // 3D node-release seam of a generated block: a slit through the leading point as wide as the needle,
  // whose lips take the lip wedge (chooseSeam)
  bool slit3d_ = false;
  bool touched_ = false;  // the needle touched a tissue node (requireContact)
  double seamY_ = 0.0, sleeveRadius_ = 0.0;
  // mesh and its seam pairs (original, copy); thickness_: slab thickness of a 2D model
  Mesh mesh_;
  std::vector<std::pair<int, int>> seam_;
  SleeveMesh sleeveMesh_;
  double thickness_ = 1.0;
  double dmax_ = 0.0;  // deepest tip position plus two core elements
  CrackPathSetup crackPath_;
  std::vector<CohesiveLaw> cohLaws_;
  std::vector<double> cohGc_;  // per node: G_c of its pair
  std::vector<std::vector<int>> inclusionNodes_;
  std::unique_ptr<ExplicitSolver> solver_;
  std::unique_ptr<DeformableNeedle> beam_;
  // records
  std::unique_ptr<ContactOutput> contactOut_;
  std::unique_ptr<results::ForcesTable> forces_;
  io::Table energy_, contact_, seam_table_;
  results::InclusionMotion inclusions_;
  io::FieldSeries* fields_ = nullptr;
  io::FieldSeries* needleFields_ = nullptr;
  double duration_ = 0.0, depth0_ = 0.0;
  double peak_ = 0, peakTorque_ = 0, peakArea_ = 0, peakPressure_ = 0;
  double ratioMax_ = 0, balanceMax_ = 0, energyScale_ = 1e-300, needleBalanceMax_ = 0, needleWorkMax_ = 1e-300;
  double cohGcArea_ = 0.0;  // sum G_c x tributary length over the fully damaged pairs (J/m)
  engines::RealtimeMarkers markers_;  // model.explicit.markers (marker_location.hpp)
};

}  // namespace needlesim::explicit_fe
