// model.realtime2d, each field declared once (scenario/parameter_table.hpp), and the markers
// and entry-angle refusal the real-time engines share.
#include "needlesim/engines/realtime2d/realtime2d_section.hpp"

#include <fmt/format.h>

#include <cmath>
#include <numbers>

#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::engines {

std::vector<MarkerSpec> readRealtimeMarkers(scenario::Section& engine, const Scenario& sc, bool with_z) {
  std::vector<MarkerSpec> out;
  auto list = engine.list("markers");
  const double ylo = -0.5 * sc.tissue.width - sc.insertion.entry_offset, yhi = ylo + sc.tissue.width;
  const double zmax = 0.5 * sc.tissue.height;
  for (std::size_t i = 0; i < list.size(); ++i) {
    scenario::Section m = engine.element(list[i], "markers", i);
    MarkerSpec mk{m.text("name"), m.number("x"), m.number("y"), with_z ? m.number("z") : 0.0};
    const bool inside = mk.x <= sc.tissue.length && mk.y >= ylo && mk.y <= yhi && std::abs(mk.z) <= zmax;
    if (!inside && !with_z)
      throw m.error("x", fmt::format("({:g}, {:g}) mm", mk.x * 1e3, mk.y * 1e3), "lies outside the tissue block",
                    fmt::format("0 <= x <= {:g} mm and {:g} mm <= y <= {:g} mm", sc.tissue.length * 1e3,
                                ylo * 1e3, yhi * 1e3));
    if (!inside)
      throw m.error(!(mk.x <= sc.tissue.length) ? "x" : !(mk.y >= ylo && mk.y <= yhi) ? "y" : "z",
                    fmt::format("({:g}, {:g}, {:g}) mm", mk.x * 1e3, mk.y * 1e3, mk.z * 1e3),
                    "lies outside the tissue block",
                    fmt::format("0 <= x <= {:g} mm, {:g} mm <= y <= {:g} mm, |z| <= {:g} mm", sc.tissue.length * 1e3,
                                ylo * 1e3, yhi * 1e3, zmax * 1e3));
    for (const auto& o : out)
      if (o.name == mk.name) throw m.error("name", mk.name, "is used by two markers", "unique names");
    out.push_back(mk);
  }
  return out;
}

void refuseShallowEntry(const Scenario& sc, const std::string& engine) {
  if (sc.model.engine != engine || sc.insertion.entry_angle >= 0.25 * std::numbers::pi - 1e-12) return;
  throw InputError(sc.where("insertion.entry_angle"), "insertion.entry_angle",
                   fmt::format("{:g} deg", sc.insertion.entry_angle * 180.0 / std::numbers::pi),
                   "is below the 45 deg that engine " + engine +
                       " supports (its path-node coupling needs the needle within 45 deg of the entry-face normal)",
                   "45 deg to 90 deg for engine " + engine);
}

namespace {

using Spec = Realtime2dModelSpec;
using scenario::Section;

// element_size instead of the node counts: a uniform mesh of that size.
void readMeshSize(Section& rt, Spec& r, const Scenario& sc) {
  auto h = rt.optNumber("element_size");
  if (!h) {
    r.nodes_depth = static_cast<int>(rt.number("nodes_depth"));  // whole numbers (schema)
    r.nodes_lateral = static_cast<int>(rt.number("nodes_lateral"));
    return;
  }
  if (rt.has("nodes_depth") || rt.has("nodes_lateral"))
    throw rt.error("element_size", "", "give element_size or the node counts, not both",
                   "element_size, or nodes_depth and nodes_lateral");
  r.element_size = *h;
  r.nodes_depth = static_cast<int>(std::lround(sc.tissue.length / *h)) + 1;
  r.nodes_lateral = static_cast<int>(std::lround(sc.tissue.width / *h)) + 1;
  if (r.nodes_depth < 2 || r.nodes_lateral < 3 || r.nodes_depth * r.nodes_lateral > 4000000)
    throw rt.error("element_size", fmt::format("{:g} mm", *h * 1e3),
                   fmt::format("gives {} x {} nodes for the {:g} x {:g} mm block", r.nodes_depth, r.nodes_lateral,
                               sc.tissue.length * 1e3, sc.tissue.width * 1e3),
                   "at least 2 x 3 and at most 4 million nodes");
}

void readSprings(Section& rt, Spec& r, const Scenario&) {
  if (r.spring_boundary) {
    auto k = rt.optNumber("spring_stiffness");
    if (!k) throw rt.error("spring_stiffness", "", "is required for boundary: springs", "> 0 N/m^3");
    r.spring_stiffness = *k;
  } else if (rt.has("spring_stiffness")) {
    throw rt.error("spring_stiffness", "", "only applies to boundary: springs", "boundary: springs");
  }
}

scenario::ParamTable<Spec> build() {
  using namespace scenario;
  namespace D = units::dim;
  ParamTable<Spec> t("realtime2d");
  t.row(numberDoc("realtime2d", "element_size", D::Length, positive(), "",
                  "element size of a uniform mesh (instead of the node counts)"),
        readMeshSize)
      .count(&Spec::nodes_depth, "nodes_depth", 2.0, 2000.0, "nodes along the insertion axis (block.length)")
      .count(&Spec::nodes_lateral, "nodes_lateral", 3.0, 2000.0,
             "nodes across it (block.width); a node row lies on the path");
  t.docOnly(2);  // the node counts: read with element_size
  t.number(&Spec::refinement, "refinement", closed(1.0, 100.0),
           "coarsest / finest lateral element size; the finest elements lie on the needle path")
      .choice(&Spec::plane_strain, "plane", {{"strain", true}, {"stress", false}}, "plane strain or plane stress")
      .quantity(&Spec::thickness, "thickness", D::Length, "mm", positive(), "out-of-plane extent of the 2D slab")
      .choice(&Spec::lumped_mass, "mass", {{"consistent", false}, {"lumped", true}}, "mass matrix (seed 003 eq 3.7)")
      .quantity(&Spec::rayleigh_alpha, "rayleigh_alpha", D::Frequency, "1/s", nonNegative(),
                "mass-proportional Rayleigh damping (seed 003 eq 3.8)")
      .quantity(&Spec::rayleigh_beta, "rayleigh_beta", D::Time, "s", nonNegative(),
                "stiffness-proportional Rayleigh damping (seed 003 eq 3.8)")
      .number(&Spec::newmark_gamma, "newmark_gamma", closed(0.5, 1.0),
              "Newmark gamma (delta of seed 003 eq 3.2); below 1/2 the scheme amplifies every mode")
      .number(&Spec::newmark_beta, "newmark_beta", openClosed(0.0, 1.0), "Newmark beta (seed 003 eq 3.3)")
      .choice(&Spec::spring_boundary, "boundary", {{"held", false}, {"springs", true}},
              "held: all sides but the entry face fixed (seed 003 section 3.5); springs: spring supports there")
      .row(numberDoc("realtime2d", "spring_stiffness", units::Dim{-2, 1, -2, 0}, positive(), "",
                     "support stiffness per boundary area (N/m^3), for boundary: springs"),
           readSprings)
      .word(&Spec::solver, "solver", {"auto", "direct", "modal", "reduced"},
            "direct: sparse LDLT; modal: all modes (exact); reduced: truncated modes plus residual flexibility "
            "(10k-node meshes); auto: modal up to 2600 free DOFs, else reduced")
      .derived(&Spec::tip_load_ratio, "tip_load_ratio", D::None, nonNegative(), "cot(bevel_angle)",
               [](const Spec&, const Scenario& sc) { return 1.0 / std::tan(sc.needle.bevel_angle); },
               "transverse bevel load per unit cutting force")
      .quantity(&Spec::field_interval, "field_interval", D::Time, "s", nonNegative(),
                "interval of the tissue field output for ParaView (0 = none)")
      .row(t.otherDoc("markers", Kind::List, "", "tissue points whose displacement is reported", "marker"),
           [](Section& s, Spec& r, const Scenario& sc) { r.markers = readRealtimeMarkers(s, sc, false); })
      .choice(&Spec::relaxation, "relaxation", {{"prony", true}, {"off", false}},
              "prony: the material's Prony terms relax the whole tissue stiffness (QLV); off: elastic")
      .number(&Spec::stiffening_factor, "stiffening_factor", closed(1.0, 1000.0),
              "Young's modulus factor of the tissue around the needle path (seed 003 section 3.5 item 4)")
      .quantity(&Spec::stiffening_radius, "stiffening_radius", D::Length, "mm", nonNegative(),
                "half-width of the stiffened zone around the path line");
  return t;
}

const scenario::ParamTable<Spec>& table() {
  static const auto t = build();
  return t;
}

std::vector<scenario::FieldDoc> docs() {
  using namespace scenario;
  std::vector<FieldDoc> out = table().docs();
  for (auto& f : realtimeMarkerDocs(false, "lateral distance from the needle path line (through the entry point)"))
    out.push_back(f);
  return out;
}

}  // namespace

std::vector<scenario::FieldDoc> realtimeMarkerDocs(bool with_z, const std::string& y_help) {
  using namespace scenario;
  const std::string section = with_z ? "marker3d" : "marker";
  ParamTable<MarkerSpec> m(section);
  m.row(m.otherDoc("name", Kind::String, "", "label in results"))
      .row(numberDoc(section, "x", units::dim::Length, nonNegative(), "", "depth from the entry face"))
      .row(numberDoc(section, "y", units::dim::Length, anyValue(), "", y_help));
  std::vector<FieldDoc> out;
  for (auto f : m.docs()) {
    f.required = true;
    out.push_back(f);
  }
  if (with_z)
    out.push_back(numberDoc(section, "z", units::dim::Length, anyValue(),
                            defaultText(MarkerSpec{}.z, units::dim::Length, "mm"),
                            "distance from the insertion plane (mid-height of the block)"));
  return out;
}

const scenario::ModelSection& realtime2dSection() {
  static const scenario::ModelSection s{
      "realtime2d", "parameters of the real-time 2D FE engine", docs, [](scenario::Section& sec, Scenario& sc) {
        refuseShallowEntry(sc, "realtime2d");
        table().read(sec, sc.model.realtime2d, sc);
      }};
  return s;
}

}  // namespace needlesim::engines
