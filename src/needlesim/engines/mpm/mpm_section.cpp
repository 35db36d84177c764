// model.mpm, each field declared once (scenario/parameter_table.hpp), and the refusals of
// settings mpm cannot run (too few points across the block, too many grid nodes).
#include "needlesim/engines/mpm/mpm_section.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "needlesim/scenario/measured_data.hpp"
#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {
namespace {

using Spec = MpmModelSpec;
using scenario::Section;
constexpr const char* kFaces[6] = {"entry", "exit", "y_min", "y_max", "z_min", "z_max"};

// The spacings against each other, and (when mpm runs) against the block.
void checkSpacings(Section& s, Spec& m, const Scenario& sc) {
  if (m.particle_spacing > m.grid_spacing)
    throw s.error("particle_spacing", fmt::format("{:g} mm", m.particle_spacing * 1e3),
                  "is larger than the grid spacing (cells without material points)",
                  fmt::format("<= grid_spacing = {:g} mm", m.grid_spacing * 1e3));
  if (sc.model.engine != "mpm") return;
  const double minSide = std::min({sc.tissue.length, sc.tissue.width, sc.tissue.height});
  if (m.particle_spacing > 0.5 * minSide)
    throw s.error("particle_spacing", fmt::format("{:g} mm", m.particle_spacing * 1e3),
                  "leaves fewer than 2 material points across the block", fmt::format("<= {:g} mm", 0.5 * minSide * 1e3));
  const double cells = (sc.tissue.length / m.grid_spacing + 7) * (sc.tissue.width / m.grid_spacing + 7) *
                       (sc.tissue.height / m.grid_spacing + 7);
  const double points = sc.tissue.length * sc.tissue.width * sc.tissue.height / std::pow(m.particle_spacing, 3);
  if (cells > 5e7 || points > 2e7)
    throw s.error("grid_spacing", fmt::format("{:g} mm", m.grid_spacing * 1e3),
                  fmt::format("gives {:.3g} grid nodes and {:.3g} material points for the block", cells, points),
                  "at most 5e7 nodes and 2e7 points (coarser spacings)");
}

void readFaces(Section& s, Spec& m, const Scenario&) {
  Section faces = s.sub("faces");
  for (std::size_t f = 0; f < 6; ++f) m.faces[f] = faces.choice(kFaces[f]);
}

void readMarkers(Section& s, Spec& m, const Scenario& sc) {
  auto markers = s.list("markers");
  for (std::size_t i = 0; i < markers.size(); ++i) {
    Section e = s.element(markers[i], "markers", i);
    MpmMarkerSpec mk{e.text("name"), e.number("x"), e.number("y"), e.number("z")};
    const double ylo = -0.5 * sc.tissue.width - sc.insertion.entry_offset, yhi = ylo + sc.tissue.width;
    if (mk.x > sc.tissue.length || !(mk.y >= ylo && mk.y <= yhi) || std::abs(mk.z) > 0.5 * sc.tissue.height)
      throw e.error("x", fmt::format("({:g}, {:g}, {:g}) mm", mk.x * 1e3, mk.y * 1e3, mk.z * 1e3),
                    "lies outside the tissue block",
                    fmt::format("0 <= x <= {:g} mm, {:g} mm <= y <= {:g} mm, |z| <= {:g} mm", sc.tissue.length * 1e3,
                                ylo * 1e3, yhi * 1e3, 0.5 * sc.tissue.height * 1e3));
    for (const auto& o : m.markers)
      if (o.name == mk.name) throw e.error("name", mk.name, "is used by two markers", "unique names");
    m.markers.push_back(mk);
  }
}

// A measured data file, resolved against the scenario file.
std::string measuredFile(Section& s, const Scenario& sc, const char* field, const char* allowed) {
  std::string f = s.text(field);
  if (f.empty()) return f;
  std::filesystem::path p(f);
  if (p.is_relative()) {
    std::filesystem::path base = std::filesystem::path(sc.source).parent_path();
    if (!base.empty()) p = base / p;
  }
  if (!std::filesystem::exists(p))
    throw s.error(field, f, "does not exist (paths are relative to the scenario file)", allowed);
  return p.string();
}

void readMeasured(Section& s, Spec& m, const Scenario& sc) {
  m.measured_force.path = measuredFile(s, sc, "measured_force", "a CSV file with columns 'depth [mm]' and 'force [N]'");
  m.measured_markers.path = measuredFile(
      s, sc, "measured_markers", "a CSV file with 'depth [mm]' and per marker '<name>_ux [mm]', '<name>_uy [mm]'");
  if (!m.measured_markers.path.empty() && m.markers.empty())
    throw s.error("measured_markers", m.measured_markers.path, "has nothing to compare with",
                  "model.mpm.markers naming the measured markers");
  scenario::loadMeasuredData(m);  // InputError naming the file, line or column
}

scenario::ParamTable<Spec> build() {
  using namespace scenario;
  namespace D = units::dim;
  ParamTable<Spec> t("mpm");
  t.quantity(&Spec::grid_spacing, "grid_spacing", D::Length, "mm", positive(),
             "background grid spacing h (seed 000 section 4.3: 0.8 mm)")
      .derived(&Spec::particle_spacing, "particle_spacing", D::Length, positive(), "grid_spacing / 2",
               [](const Spec& m, const Scenario&) { return 0.5 * m.grid_spacing; },
               "material point spacing (seed 000 section 4.3: 0.4 mm)");
  t.check(checkSpacings);
  t.choice(&Spec::bspline, "shape", {{"linear", false}, {"bspline", true}},
           "shape functions: linear (the paper's) or quadratic B-spline (removes the cross-cell noise of seed 000 section 5.2)")
      .choice(&Spec::fbar, "anti_locking", {{"none", false}, {"fbar", true}},
              "volumetric anti-locking for nearly incompressible tissue: none, or fbar (stress at F-bar with the "
              "cell-averaged det F; docs/models/mpm.md)")
      .choice(&Spec::musl, "update", {{"usl", false}, {"musl", true}}, "update-stress-last or modified USL (momentum remap)")
      .choice(&Spec::cfemp, "contact", {{"grid", false}, {"cfemp", true}},
              "needle-tissue contact: cfemp (particle-to-surface contact with the triangulated needle surface, seed 000 "
              "eqs 22-24; with the parting cut it agrees with explicit 3D, docs/validation/agreement.md) or grid "
              "(multi-field grid contact, eqs 14-21: it acts up to a cell into the tissue, a needle about a cell wider; "
              "the one the GPU path (device: cuda) and sliding inclusions run)")
      .quantity(&Spec::cfemp_element_size, "cfemp_element_size", D::Length, "mm", nonNegative(),
                "d_e of the CFEMP gap rule g < (d_e + d_p)/2 (seed 000 eq 22); 0 = contact when the particle's own half "
                "spacing reaches the exact needle surface")
      .word(&Spec::parting, "parting", {"tip", "path", "none"},
            "the tissue parts along the needle's cut, the strip of the plane through the axis normal to the bevel side "
            "as wide as the needle: no material point reaches a grid node across it, so the two "
            "lips move apart instead of being dragged as one field (docs/models/mpm.md \"Parting contact\"). tip: "
            "cut from the entry to where the tip reaches the plane, as it advances; path: pre-cut from the entry to "
            "the insertion's deepest point; none: one velocity field across the path. Bevel tips only: a cone or a flat "
            "tip has no cutting edge and pushes the tissue aside")
      .word(&Spec::cut, "cut", {"axis", "edges"},
            "where the parting cut of a bevel runs: axis, the strip through the axis normal to the bevel side, which "
            "opens each lip by half the needle (the axial force agrees with explicit 3D, a bevel's lateral force is "
            "not resolved); edges (contact: cfemp), the lower half of the needle's surface, which the bevel's "
            "cutting edges sweep from the sharp point: the face lifts what lies inside the needle's outline and the "
            "tissue below it stays, so the bevel pushes the needle away from its face (docs/models/mpm.md \"Parting "
            "contact\")")
      .derived(&Spec::tip_friction, "tip_friction", D::None, nonNegative(), "tissue friction.coefficient",
               [](const Spec&, const Scenario& sc) {
                 return sc.tissue.layers.empty() ? 0.0 : sc.tissue.layers.front().friction.coefficient;
               },
               "CFEMP: Coulomb coefficient on the tip's surface (the bevel face, the cone), the shaft's being the "
               "tissue's friction.coefficient (seed 000: one coefficient, the default; seed 001 and explicit 3D's "
               "tip_friction: a frictionless tip, 0)")
      .number(&Spec::flip, "flip", closed(0.0, 1.0), "FLIP fraction of the particle velocity update (1 = seed 000 eq 4, 0 = PIC)")
      .number(&Spec::time_step_factor, "time_step_factor", openClosed(0.0, 1.0),
              "k_t of seed 000 eq 26 (time step = k_t times the eq 25 limit)")
      .number(&Spec::mass_scaling, "mass_scaling", closed(1.0, 1e12),
              "factor on every particle mass (seed 000 eq 28 discussion: 1e4); the time step grows with its square root")
      .count(&Spec::margin, "margin", 2.0, 100.0, "grid cells beyond the tissue block on each side")
      .count(&Spec::threads, "threads", 0.0, 1024.0,
             "OpenMP threads (0 = all cores; more than the hardware threads are capped, with a warning)")
      .choice(&Spec::cuda, "device", {{"cpu", false}, {"cuda", true}},
              "where the steps run: cpu (OpenMP threads), or cuda (the GPU plugin libneedlesim_mpm_cuda.so, built where "
              "nvcc is found; refused with the reason where it is missing, no GPU is present or the scenario uses "
              "what the GPU path lacks: docs/architecture.md \"MPM on the GPU\")")
      .row(t.otherDoc("faces", Kind::Section, "exit fixed, others free", "boundary condition of each face of the block",
                      "mpm_faces"),
           readFaces)
      .quantity(&Spec::field_interval, "field_interval", D::Time, "s", nonNegative(),
                "interval of the particle fields (displacement, von Mises) for ParaView (0 = none)")
      .quantity(&Spec::marker_depth_step, "marker_depth_step", D::Length, "mm", nonNegative(),
                "record the markers each time the tip advances this far (seed 000: 3 mm); 0 = at the output interval")
      .row(t.otherDoc("markers", Kind::List, "", "tissue points whose displacement is reported (seed 000 Fig 11)",
                      "mpm_marker"),
           readMarkers)
      .row(t.otherDoc("measured_force", Kind::String, "",
                      "CSV of a measured force curve (columns 'depth [mm]' and 'force [N]', any units); RMSE and MAE of "
                      "seed 000 eq 35 are reported. Relative to the scenario file"),
           readMeasured)
      .row(t.otherDoc("measured_markers", Kind::String, "",
                      "CSV of measured marker displacements (column 'depth [mm]' and per marker '<name>_ux [mm]', "
                      "'<name>_uy [mm]'); the errors r_max and r_mean of seed 000 eq 37 are reported per depth. "
                      "Relative to the scenario file"));
  return t;
}

const scenario::ParamTable<Spec>& table() {
  static const auto t = build();
  return t;
}

std::vector<scenario::FieldDoc> docs() {
  using namespace scenario;
  std::vector<FieldDoc> out = table().docs();
  ParamTable<Spec> faces("mpm_faces");
  for (std::size_t i = 0; i < 6; ++i) {
    const std::string k = kFaces[i];
    const std::string where = k == "entry"  ? "the entry face (depth 0)"
                              : k == "exit" ? "the face opposite the entry (depth = block.length)"
                              : k[0] == 'y' ? "a side face across the width (normal in the insertion plane)"
                                            : "a face across the height (normal out of the insertion plane)";
    FieldDoc f = faces.otherDoc(k, Kind::Choice, Spec{}.faces[i],
                                where + ": free, fixed (all velocity components zero), roller (normal component zero) or "
                                        "non-reflecting (Lysmer dashpots)");
    f.choices = {"free", "fixed", "roller", "non-reflecting"};
    out.push_back(f);
  }
  ParamTable<MpmMarkerSpec> m("mpm_marker");
  FieldDoc name = m.otherDoc("name", Kind::String, "", "label in results");
  FieldDoc x = numberDoc("mpm_marker", "x", units::dim::Length, nonNegative(), "", "depth from the entry face");
  FieldDoc y = numberDoc("mpm_marker", "y", units::dim::Length, anyValue(), "",
                         "lateral distance from the needle path line, in the insertion plane");
  for (FieldDoc* f : {&name, &x, &y}) f->required = true;
  out.insert(out.end(), {name, x, y});
  out.push_back(numberDoc("mpm_marker", "z", units::dim::Length, anyValue(),
                          defaultText(MpmMarkerSpec{}.z, units::dim::Length, "mm"),
                          "distance from the insertion plane (mid-height of the block)"));
  return out;
}

}  // namespace

const scenario::ModelSection& mpmSection() {
  static const scenario::ModelSection s{
      "mpm", "parameters of the 3D material point method engine (seed 000)", docs,
      [](scenario::Section& sec, Scenario& sc) { table().read(sec, sc.model.mpm, sc); }};
  return s;
}

}  // namespace needlesim::engines
