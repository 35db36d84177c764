// model.realtime3d, each field declared once (scenario/parameter_table.hpp).
#include "needlesim/engines/realtime3d/realtime3d_section.hpp"

#include <cmath>

#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {
namespace {

using Spec = Realtime3dModelSpec;
using scenario::Section;

scenario::ParamTable<Spec> build() {
  using namespace scenario;
  namespace D = units::dim;
  ParamTable<Spec> t("realtime3d");
  t.count(&Spec::nodes_depth, "nodes_depth", 3.0, 2000.0, "nodes along the insertion axis (block.length)")
      .count(&Spec::nodes_lateral, "nodes_lateral", 3.0, 400.0, "nodes across block.width; a grid line lies on the path")
      .count(&Spec::nodes_height, "nodes_height", 3.0, 400.0, "nodes across block.height")
      .number(&Spec::refinement, "refinement", closed(1.0, 100.0),
              "coarsest / finest lateral element size; the finest elements lie on the needle path")
      .choice(&Spec::lumped_mass, "mass", {{"consistent", false}, {"lumped", true}}, "mass matrix (seed 003 eq 3.7)")
      .quantity(&Spec::rayleigh_alpha, "rayleigh_alpha", D::Frequency, "1/s", nonNegative(),
                "mass-proportional Rayleigh damping (seed 003 eq 3.8)")
      .quantity(&Spec::rayleigh_beta, "rayleigh_beta", D::Time, "s", nonNegative(),
                "stiffness-proportional Rayleigh damping (seed 003 eq 3.8)")
      .number(&Spec::newmark_gamma, "newmark_gamma", closed(0.5, 1.0),
              "Newmark gamma (delta of seed 003 eq 3.2); below 1/2 the scheme amplifies every mode")
      .number(&Spec::newmark_beta, "newmark_beta", openClosed(0.0, 1.0), "Newmark beta (seed 003 eq 3.3)")
      .quantity(&Spec::coupling_spacing, "coupling_spacing", D::Length, "mm", closed(1e-4, 5e-2),
                "spacing of the points along the needle path where the shaft couples to the tissue (embedded in the "
                "tets, whatever the mesh); the step must not carry the tip past one")
      .choice(&Spec::hold_sides, "boundary", {{"held", true}, {"far-face", false}},
              "held: all faces but the entry face fixed (seed 003 section 3.5); far-face: only the face opposite the "
              "entry (tissue.geometry: its supported side, tissue.geometry.support_depth, either way)")
      .word(&Spec::solver, "solver", {"auto", "direct", "modal", "reduced"},
            "direct: sparse LDLT; modal: all modes (exact); reduced: lowest modes plus residual flexibility "
            "(10k-node blocks at kHz rates); auto: modal up to 1500 free DOFs, else reduced")
      .count(&Spec::modes, "modes", 1.0, 2000.0, "reduced: most kept modes (the rest: residual flexibility)")
      .derived(&Spec::tip_load_ratio, "tip_load_ratio", D::None, nonNegative(), "cot(bevel_angle)",
               [](const Spec&, const Scenario& sc) { return 1.0 / std::tan(sc.needle.bevel_angle); },
               "transverse bevel load per unit cutting force")
      .quantity(&Spec::field_interval, "field_interval", D::Time, "s", nonNegative(),
                "interval of the tissue field output for ParaView (0 = none)")
      .choice(&Spec::relaxation, "relaxation", {{"prony", true}, {"off", false}},
              "prony: the material's Prony terms relax the whole tissue stiffness (QLV); off: elastic")
      .choice(&Spec::follow_tip, "path", {{"straight", false}, {"follow_tip", true}},
              "straight: the path points lie on the reference axis; follow_tip: each is placed where the tip "
              "reaches its depth, on the channel the tip cuts turning towards the bevel at `curvature` (kinematic "
              "bevel-tip model, Webster et al. 2006), and holds the shaft there")
      .row(numberDoc("realtime3d", "curvature", units::Dim{-1, 0, 0, 0}, nonNegative(),
                     "model.steering.curvature, else from the tip loads",
                     "path follow_tip: curvature of the channel with the bevel fixed; omitted = as engine kinematic "
                     "(model.steering.curvature, else the beam-on-foundation steady curvature (M + Q/lambda)/EI)"),
           [](Section& s, Spec& r, const Scenario&) { r.curvature = s.optNumber("curvature").value_or(-1.0); })
      .row(t.otherDoc("markers", Kind::List, "", "tissue points whose displacement is reported", "marker3d"),
           [](Section& s, Spec& r, const Scenario& sc) { r.markers = readRealtimeMarkers(s, sc, true); });
  return t;
}

const scenario::ParamTable<Spec>& table() {
  static const auto t = build();
  return t;
}

std::vector<scenario::FieldDoc> docs() {
  using namespace scenario;
  std::vector<FieldDoc> out = table().docs();
  for (auto& f : realtimeMarkerDocs(
           true, "lateral distance from the needle path line (through the entry point), in the insertion plane"))
    out.push_back(f);
  return out;
}

}  // namespace

const scenario::ModelSection& realtime3dSection() {
  static const scenario::ModelSection s{"realtime3d", "parameters of the real-time 3D FE engine (tetrahedral block)",
                                        docs, [](scenario::Section& sec, Scenario& sc) {
                                          refuseShallowEntry(sc, "realtime3d");
                                          table().read(sec, sc.model.realtime3d, sc);
                                        }};
  return s;
}

}  // namespace needlesim::engines
