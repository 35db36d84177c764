// model.steering (engines kinematic, energy, beam-foundation), each field declared once
// (scenario/parameter_table.hpp).
#include "needlesim/engines/steering/steering_section.hpp"

#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {
namespace {

using Spec = SteeringModelSpec;

scenario::ParamTable<Spec> build() {
  using namespace scenario;
  namespace D = units::dim;
  ParamTable<Spec> t("steering");
  // Not given: the engine computes the beam-on-foundation steady curvature from the tip loads.
  t.row(numberDoc("steering", "curvature", units::Dim{-1, 0, 0, 0}, nonNegative(), "from the tip loads",
                  "kinematic: curvature with the bevel fixed (e.g. 3.3 1/m); omitted = the beam-on-foundation "
                  "steady curvature (M + Q/lambda)/EI of the tip loads"),
        [](Section& s, Spec& st, const Scenario&) { st.curvature = s.optNumber("curvature").value_or(-1.0); });
  t.number(&Spec::beta_over_alpha, "beta_over_alpha", openClosed(0.0, 1.0),
           "cut angle / bevel angle (seed 002 sections 3.1, 5.2)")
      .quantity(&Spec::input_force, "input_force", D::Force, "mN", positive(),
                "insertion force P_input (seed 002 section 5.2)")
      .word(&Spec::tip_load, "tip_load", {"roller", "bevel-edges"},
            "transverse tip load of beam-foundation (and of kinematic without curvature): roller = the "
            "sub-step-1 roller reaction P_input/tan(beta) that drives seed 002's section 5 model; "
            "bevel-edges = eqs 24-26 from K_T and the bevel geometry")
      .word(&Spec::energy_frame, "energy_frame", {"entry", "path-window"},
            "energy model trial functions: entry = clamped at the entry and spanning the inserted length "
            "(the paper's eq 45 reading); path-window = Hermite pieces over 4 (4EI/K_T)^(1/4) behind the tip "
            "in a frame attached to the cut path (circular paths; docs/models/bevel-tip-energy.md choice 9)")
      .quantity(&Spec::increment, "increment", D::Length, "mm", positive(),
                "insertion increment (beam-foundation element length; path sampling)")
      .number(&Spec::friction_dissipation, "friction_dissipation", closedOpen(0.0, 1.0),
              "energy: share of the input work dissipated by friction (seed 002 Fig 23)")
      .derived(&Spec::tear_length, "tear_length", D::Length, nonNegative(), "needle radius",
               [](const Spec&, const Scenario& sc) { return sc.needle.outer_diameter / 2; },
               "energy: tear length a of seed 002 eq 44")
      .quantity(&Spec::fracture_energy, "fracture_energy", D::ForcePerLength, "N/m", nonNegative(),
                "energy: fracture energy G_f per torn area in W_R = a G_f l (eq 44); with the tear length it sets the "
                "share 1 - a G_f / P_input of the push that cuts sideways (docs/models/bevel-tip-energy.md choice 10)")
      .quantity(&Spec::max_step, "max_step", D::Length, "mm", positive(), "energy: largest advance of one increment")
      .count(&Spec::snapshots, "snapshots", 1.0, 100.0, "needle shapes recorded along the insertion");
  return t;
}

const scenario::ParamTable<Spec>& table() {
  static const auto t = build();
  return t;
}

}  // namespace

const scenario::ModelSection& steeringSection() {
  static const scenario::ModelSection s{
      "steering", "parameters of the steering engines kinematic, energy and beam-foundation",
      [] { return table().docs(); },
      [](scenario::Section& sec, Scenario& sc) { table().read(sec, sc.model.steering, sc); }};
  return s;
}

}  // namespace needlesim::engines
