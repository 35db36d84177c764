// model.explicit and model.explicit.cohesive, each field declared once
// (scenario/parameter_table.hpp), and the refusals of settings the engine cannot run.
#include "needlesim/engines/explicit/explicit_section.hpp"

#include <fmt/format.h>

#include <cmath>

#include "needlesim/engines/explicit/cohesive_path_section.hpp"
#include "needlesim/insertion/motion_profile.hpp"
#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {
namespace {

using Spec = ExplicitModelSpec;
using Cohesive = ExplicitCohesiveSpec;
using scenario::Section;

// A sleeve seam needs a 3d hollow bevel needle; a cohesive seam needs t_c and G_c.
void checkCohesive(Section& cs, Cohesive& c, const Spec& x, const Scenario& sc) {
  if (c.enable && c.seam == "sleeve") {
    const double ro = 0.5 * sc.needle.outer_diameter, ri = 0.5 * sc.needle.inner_diameter;
    if (x.dimension != 3 || !(ri > 0) || sc.needle.tip != TipType::Bevel)
      throw cs.error("seam", "sleeve", "needs a 3d model and a hollow bevel needle",
                     "plane, or dimension: 3d with needle.inner_diameter > 0 and tip: bevel");
    if (c.sleeve_radius != 0 && !(c.sleeve_radius > ri && c.sleeve_radius < ro))
      throw cs.error("sleeve_radius", fmt::format("{:g} mm", c.sleeve_radius * 1e3),
                     "is not between the needle's inner and outer radius",
                     fmt::format("{:g} mm < sleeve_radius < {:g} mm, or 0", ri * 1e3, ro * 1e3));
  }
  if (!c.enable) return;
  if (c.strength <= 0 && c.critical_separation <= 0)
    throw cs.error("strength", "0", "is not given and neither is critical_separation",
                   "strength (t_c) or critical_separation (delta_c, t_c = 2 G_c / delta_c)");
  if (c.fracture_energy <= 0)
    for (const auto& l : sc.tissue.layers)
      if (l.toughness <= 0)
        throw cs.error("fracture_energy", "0", "is not given and a layer has no interaction.toughness",
                       "fracture_energy, or interaction.toughness in every layer");
}

scenario::ParamTable<Cohesive> cohesiveTable() {
  using namespace scenario;
  namespace D = units::dim;
  ParamTable<Cohesive> t("explicit_cohesive");
  t.flag(&Cohesive::enable, "enable", "put the cohesive law on the seam pairs (needs pre_cut; quad4 or hex8)")
      .quantity(&Cohesive::stiffness, "stiffness", units::Dim{-2, 1, -2, 0}, "N/m^3", nonNegative(),
                "initial stiffness K = K_n = K_s (traction per separation); 0 = E / constitutive_thickness, or 10 "
                "E'/element_size without it")
      .quantity(&Cohesive::constitutive_thickness, "constitutive_thickness", D::Length, "mm", nonNegative(),
                "seed 004's T0: K = E / T0 (E of the layer) when stiffness is 0")
      .quantity(&Cohesive::strength, "strength", D::Pressure, "Pa", nonNegative(),
                "normal (and shear) strength t_c; 0 = from critical_separation")
      .quantity(&Cohesive::critical_separation, "critical_separation", D::Length, "mm", nonNegative(),
                "seed 004's delta_c: t_c = 2 G_c / delta_c when strength is 0")
      // Not given: each layer's toughness (one value per layer, so none is recorded here).
      .row(numberDoc("explicit_cohesive", "fracture_energy", D::ForcePerLength, nonNegative(), "",
                     "mode-I fracture energy G_Ic; absent = each layer's toughness"),
           [](Section& s, Cohesive& c, const Scenario&) { c.fracture_energy = s.optNumber("fracture_energy").value_or(0.0); })
      .number(&Cohesive::mode_ii_ratio, "mode_ii_ratio", positive(), "G_IIc / G_Ic (mixed mode: linear energy criterion)")
      .word(&Cohesive::path, "path", {"straight", "points", "arc", "steering"},
            "crack path = needle axis path (2d): straight; points (path_points); arc (path_radius); steering (the tip "
            "path the kinematic bevel-tip model predicts before the run); the rigid needle follows it "
            "(docs/models/cohesive.md, \"Crack path\")")
      .row(t.otherDoc("path_points", Kind::List, "",
                      "path: points: the needle axis path from the entry point (x 0, y 0), x increasing, inside the "
                      "block, each segment within 45 deg of the axis",
                      "path_point"))
      .row(t.otherDoc("path_file", Kind::String, "",
                      "path: points from a CSV file instead of path_points: columns 'x [mm]' and 'y [mm]' (any length "
                      "unit), relative to the scenario file"))
      .quantity(&Cohesive::path_radius, "path_radius", D::Length, "mm", anyValue(),
                "path: arc: radius of curvature, + curving towards +y (the bevel side at bevel_orientation 0), - "
                "towards -y")
      .docOnly(4)  // path, path_points, path_file, path_radius: readCohesivePath
      .word(&Cohesive::seam, "seam", {"plane", "sleeve"},
            "plane: the seam plane along the path (3D: through the needle axis); sleeve (3d hex8, hollow bevel needle): "
            "a cylinder around the axis that the needle wall cuts, the core entering the bore (seed 001 3.2; "
            "docs/models/cohesive.md \"Sleeve seam\")")
      .quantity(&Cohesive::sleeve_radius, "sleeve_radius", D::Length, "mm", nonNegative(),
                "radius of the sleeve seam, between the needle's inner and outer radius; 0 = the wall's mid radius");
  return t;
}

const scenario::ParamTable<Cohesive>& cohesive() {
  static const auto t = cohesiveTable();
  return t;
}

void readCohesive(Section& s, Spec& x, const Scenario& sc) {
  Section cs = s.sub("cohesive");
  cohesive().read(cs, x.cohesive, sc);
  readCohesivePath(cs, x, x.cohesive, sc);  // crack path (cohesive_path_section.cpp)
  checkCohesive(cs, x.cohesive, x, sc);
}

// The element type: given, or quad4 in 2d and hex8 in 3d.
void readElement(Section& s, Spec& x, const Scenario&) {
  if (s.has("element")) {
    x.element = s.choice("element");
  } else {
    x.element = x.dimension == 2 ? "quad4" : "hex8";
    s.remember("element", x.element);
  }
  const bool is2d = x.dimension == 2;
  if ((x.element == "quad4" || x.element == "tri3") != is2d)
    throw s.error("element", x.element, "does not match the dimension", is2d ? "quad4 or tri3 for 2d" : "hex8 or tet4 for 3d");
}

// tip: bonded is seed 004's plane-strain reading of Fig 13a: a 2d quad4 block, a bevel along the face normal.
void checkBondedTip(Section& s, const Spec& x, const Scenario& sc) {
  if (x.tip != "bonded") return;
  const auto refuse = [&](const std::string& why, const std::string& allowed) {
    throw s.error("tip", "bonded", why, allowed);
  };
  if (x.dimension != 2 || x.element != "quad4") refuse("needs a 2d quad4 model", "dimension: 2d, element: quad4");
  if (sc.needle.tip != TipType::Bevel) refuse("needs a bevel needle", "needle.tip: bevel");
  if (std::abs(sc.insertion.entry_angle - 0.5 * M_PI) > 1e-9)
    refuse("needs a needle along the entry face's normal", "insertion.entry_angle: 90 deg");
  if (sc.tissue.geometry) refuse("needs a generated block", "tissue.block instead of tissue.geometry");
  const double L = sc.needle.outer_diameter / std::tan(sc.needle.bevel_angle);
  if (!(sc.tissue.length > L + x.element_size) || !(sc.tissue.width > sc.needle.outer_diameter + 2 * x.element_size))
    refuse(fmt::format("needs a block that holds the tip ({:g} mm long, {:g} mm wide) with an element to spare",
                       L * 1e3, sc.needle.outer_diameter * 1e3),
           "a longer or wider tissue.block, or a coarser model.explicit.element_size");
}

void checkSizes(Section& s, Spec& x, const Scenario& sc) {
  checkBondedTip(s, x, sc);
  if (x.max_element_size < x.element_size)
    throw s.error("max_element_size", fmt::format("{:g} mm", x.max_element_size * 1e3), "is smaller than element_size",
                  fmt::format(">= {:g} mm", x.element_size * 1e3));
  if (x.needle_model == "beam" && !(sc.needle.youngs_modulus > 0))
    throw s.error("needle_model", "beam", "needs the needle's Young's modulus", "needle.youngs_modulus > 0");
}

scenario::ParamTable<Spec> build() {
  using namespace scenario;
  namespace D = units::dim;
  ParamTable<Spec> t("explicit");
  FieldDoc element = t.otherDoc("element", Kind::Choice, "quad4 (2d), hex8 (3d)",
                                "quad4 / hex8: one-point integration with hourglass control (CPE4R / C3D8R); tri3 / "
                                "tet4: constant strain");
  element.choices = {"quad4", "tri3", "hex8", "tet4"};
  t.choice(&Spec::dimension, "dimension", {{"2d", 2}, {"3d", 3}}, "2d (plane strain) or 3d")
      .row(element, readElement)
      .quantity(&Spec::element_size, "element_size", D::Length, "mm", positive(),
                "element size in the core around the needle path (seed 001: 0.25 mm)")
      .quantity(&Spec::max_element_size, "max_element_size", D::Length, "mm", positive(),
                "element size at the block boundary (seed 001: 3 mm)")
      .quantity(&Spec::core_width, "core_width", D::Length, "mm", positive(),
                "width of the refined core around the path (seed 001: 6 mm)")
      .number(&Spec::grading, "grading", closed(1.0, 3.0), "size ratio of neighbouring elements outside the core")
      .number(&Spec::mass_scaling, "mass_scaling", closed(1.0, 1e12),
              "factor on the density (the stable step grows with its square root)")
      .quantity(&Spec::target_time_step, "target_time_step", D::Time, "s", nonNegative(),
                "mass-scale the elements whose stable step is below this (0 = off)")
      .number(&Spec::cfl, "cfl", openClosed(0.0, 1.0), "fraction of the stable time step used")
      .number(&Spec::bulk_viscosity_linear, "bulk_viscosity_linear", nonNegative(), "linear bulk viscosity b1 (ABAQUS default)")
      .number(&Spec::bulk_viscosity_quadratic, "bulk_viscosity_quadratic", nonNegative(),
              "quadratic bulk viscosity b2 (ABAQUS default)")
      .number(&Spec::hourglass, "hourglass", nonNegative(),
              "hourglass stiffness (1 = exact pure bending of a rectangular element)")
      .quantity(&Spec::damping, "damping", D::Frequency, "1/s", nonNegative(), "mass-proportional damping (dynamic relaxation)")
      .number(&Spec::contact_penalty, "contact_penalty", openClosed(0.0, 1e4),
              "normal contact stiffness k = penalty m/dt^2, force at the end of the step (stable for any value); a "
              "value <= 1 also applies to cohesive seam lips, which otherwise use 0.3")
      .flag(&Spec::fixed_contact_stiffness, "fixed_contact_stiffness",
            "one needle contact stiffness for the whole run, from the first contact step (default: each node keeps the "
            "stiffness of the step its contact began); needs contact_penalty 0.3-0.4 on cohesive cuts")
      .number(&Spec::tip_friction, "tip_friction", nonNegative(),
              "Coulomb coefficient on the tip surface (seed 001: frictionless); the wall uses the layer's "
              "friction.coefficient")
      .word(&Spec::needle_model, "needle_model", {"rigid", "beam"},
            "rigid: the needle moves as a rigid body; beam: an Euler-Bernoulli cantilever clamped at the base, bent by "
            "the tissue's contact resultant each step (needle.youngs_modulus; docs/models/explicit.md, \"Deformable "
            "needle\")")
      .flag(&Spec::pre_cut, "pre_cut", "pre-cut (node-release) seam along the needle path through the tip's leading point")
      .row(t.otherDoc("cohesive", Kind::Section, "enable: false",
                      "bilinear cohesive zone on the pre-cut seam instead of node release (2d quad4 lines, 3d hex8 "
                      "quadrilaterals; docs/models/cohesive.md)",
                      "explicit_cohesive"),
           readCohesive)
      .derived(&Spec::field_interval, "field_interval", D::Time, nonNegative(), "run / 20",
               [](const Spec&, const Scenario& sc) { return MotionProfile(sc.insertion).duration() / 20.0; },
               "interval of the ParaView fields")
      .word(&Spec::tip, "tip", {"contact", "bonded"},
            "contact: the needle enters the tissue through its contact; bonded (2d quad4, bevel): seed 004 Fig 13a's "
            "reading, the rigid tip bonded into a linear elastic block (the first layer's small-strain moduli) on a "
            "uniform grid of element_size, moved by the profile's travel in one static solve; results P, Q, q_x, q_y "
            "(docs/validation/cohesive.md \"Fig 13a with the tip bonded into the tissue\")")
      .row(t.otherDoc("markers", Kind::List, "",
                      "tissue points whose displacement is reported (markers.csv; x depth from the entry face, y "
                      "lateral from the path line through the entry point, z from the insertion plane, ignored in "
                      "2d), each followed from its reference position in the element that holds it",
                      "marker3d"),
           [](Section& s, Spec& r, const Scenario& sc) { r.markers = readRealtimeMarkers(s, sc, true); })
      .count(&Spec::threads, "threads", 0.0, 1024.0,
             "OpenMP threads (0 = all cores; more than the hardware threads are capped, with a warning)")
      .check(checkSizes);
  return t;
}

const scenario::ParamTable<Spec>& table() {
  static const auto t = build();
  return t;
}

std::vector<scenario::FieldDoc> docs() {
  using namespace scenario;
  std::vector<FieldDoc> out = table().docs();
  for (const auto& f : cohesive().docs()) out.push_back(f);
  FieldDoc x = numberDoc("path_point", "x", units::dim::Length, nonNegative(), "", "depth from the entry face");
  FieldDoc y = numberDoc("path_point", "y", units::dim::Length, anyValue(), "",
                         "lateral distance from the straight needle line through the entry point");
  x.required = y.required = true;
  out.insert(out.end(), {x, y});
  return out;
}

}  // namespace

const scenario::ModelSection& explicitSection() {
  static const scenario::ModelSection s{
      "explicit", "parameters of the explicit large-deformation FE engine (docs/models/explicit.md)", docs,
      [](scenario::Section& sec, Scenario& sc) { table().read(sec, sc.model.explicit_fe, sc); }};
  return s;
}

}  // namespace needlesim::engines
