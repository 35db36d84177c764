// The tables of the scenario's tissue sections (problem_sections.hpp): the tissue, a layer, a
// material and its Prony terms, an inclusion, an imported geometry and its placement, and their
// readings (a material by library name or section, a layer, an inclusion placed or a group of the
// geometry, the layers' thicknesses against the block).
#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <numbers>
#include <set>

#include "needlesim/core/nearest_name.hpp"
#include "needlesim/scenario/problem_sections.hpp"
#include "needlesim/scenario/tissue_geometry.hpp"

namespace needlesim::scenario {
namespace {

namespace D = units::dim;
using materials::MaterialSpec;

std::string libraryNames() {
  std::string s;
  for (const auto& [name, spec] : materials::materialLibrary()) s += (s.empty() ? "" : ", ") + name;
  return s;
}

std::string notInLibrary(const std::string& name) {
  std::vector<std::string> known;
  for (const auto& [known_name, spec] : materials::materialLibrary()) known.push_back(known_name);
  const std::string near = nearestName(name, known);
  return "is not a material of the built-in library" + (near.empty() ? std::string() : " (did you mean '" + near + "'?)");
}

// The parameters given in material section `m`: each must belong to the law, the law's required
// ones must be there, and the rules between them hold.
void readLawParameters(Section& m, MaterialSpec& spec) {
  const auto& allowed = materials::lawParams(spec.law);
  std::string allowedText;
  for (const auto& p : allowed) allowedText += (allowedText.empty() ? "" : ", ") + p.key;
  static const std::set<std::string> nonParams{"base", "name", "law", "density", "prony"};
  for (const auto* f : fieldsOf("material")) {
    if (nonParams.count(f->key) || !m.has(f->key)) continue;
    bool ok = false;
    for (const auto& p : allowed) ok = ok || p.key == f->key;
    if (!ok) throw m.error(f->key, m.raw(f->key).Scalar(), "is not a parameter of law '" + spec.law + "'", allowedText);
    spec.params[f->key] = m.number(f->key);
  }
  for (const auto& p : allowed)
    if (p.required && !spec.has(p.key))
      throw m.error(p.key, "", "is required for law '" + spec.law + "' but missing", allowedText);
  if (spec.has("K") && spec.has("nu") && spec.law != "linear")
    throw m.error("K", "", "give either K or nu for the volumetric part, not both", "K or nu");
  if (auto bad = materials::checkLawParams(spec)) throw m.error(bad->key, bad->value, bad->why, bad->allowed);
}

// material.prony: the terms (their g summing to less than 1) replace the base material's.
void readProny(Section& m, MaterialSpec& spec, const Scenario& sc) {
  auto terms = m.list("prony");
  if (!terms.empty()) spec.prony.clear();
  double gsum = 0.0;
  for (std::size_t i = 0; i < terms.size(); ++i) {
    Section t = m.element(terms[i], "prony", i);
    materials::PronyTerm term;
    pronyTable().read(t, term, sc);
    gsum += term.g;
    spec.prony.push_back(term);
  }
  if (gsum >= 1.0)
    throw m.error("prony", fmt::format("sum g = {:g}", gsum), "the relative moduli must sum to less than 1",
                  "sum of g_i < 1 (the long-term modulus must stay positive)");
}

// A material section: a library material (base) with the fields given over it, or a law and its parameters.
MaterialSpec readMaterialSection(Section& m, const Scenario& sc) {
  MaterialSpec spec;
  const std::string base = m.text("base");
  if (!base.empty()) {
    auto it = materials::materialLibrary().find(base);
    if (it == materials::materialLibrary().end()) throw m.error("base", base, notInLibrary(base), libraryNames());
    spec = it->second;
  }
  if (const std::string name = m.text("name"); !name.empty()) spec.name = name;
  else m.remember("name", spec.name);
  if (m.has("law")) {
    const std::string law = m.choice("law");
    if (law != spec.law) spec.params.clear();
    spec.law = law;
  } else if (base.empty()) {
    throw m.error("law", "", "is required (or give 'base')", field("material", "law").rangeText());
  }
  readLawParameters(m, spec);
  if (auto rho = m.optNumber("density"); rho && (m.has("density") || base.empty())) spec.density = *rho;
  readProny(m, spec, sc);
  // The small-strain moduli must be physical.
  const auto mod = materials::smallStrainModuli(spec);
  if (!(mod.shear > 0.0) || !(mod.bulk > 0.0))
    throw m.errorAt(m.raw("law"), m.path(), spec.law,
                    fmt::format("gives a non-positive initial shear ({:g} Pa) or bulk ({:g} Pa) modulus", mod.shear,
                                mod.bulk),
                    "parameters with a positive initial shear modulus");
  return spec;
}

// The row `material` of a layer or an inclusion: a library name or a material section.
MaterialSpec readMaterial(Section& parent, const std::string& key, const Scenario& sc) {
  YAML::Node n = parent.raw(key);
  if (n && n.IsScalar()) {
    auto it = materials::materialLibrary().find(n.Scalar());
    if (it == materials::materialLibrary().end())
      throw parent.error(key, n.Scalar(), notInLibrary(n.Scalar()),
                         libraryNames() + ", or a section with 'law' and its parameters");
    parent.remember(key, n.Scalar());
    return it->second;
  }
  Section m = parent.sub(key);
  return readMaterialSection(m, sc);
}

ParamTable<MaterialSpec> makeMaterial() {
  using M = MaterialSpec;
  ParamTable<M> t("material");
  t.row(t.otherDoc("base", Kind::String, "", "start from a library material and override the fields given"))
      .text(&M::name, "name", M{}.name, "label");
  FieldDoc law = t.otherDoc("law", Kind::Choice, "", "constitutive law (required unless base is given)");
  law.choices = materials::lawNames();
  t.row(std::move(law))
      .quantity(&M::density, "density", D::Density, "kg/m^3", positive(), "mass density");
  for (const auto& p : materials::lawParameterFields())  // each law's parameters (materials/laws/)
    t.row(numberDoc("material", p.key, p.pressure ? D::Pressure : D::None, Range{p.lo, p.hi, p.loOpen, p.hiOpen}, "",
                    p.help));
  // Read by readMaterialSection (a base material's fields stay unless given).
  t.section("prony", Kind::List, "prony", false, "", "Prony series terms (seed 001 eqs 1-4)").docOnly(t.docs().size());
  return t;
}

ParamTable<materials::PronyTerm> makeProny() {
  using P = materials::PronyTerm;
  ParamTable<P> t("prony");
  t.required(&P::g, "g", D::None, Range{0.0, 1.0, true, true}, "relative modulus g_i; the g_i must sum to less than 1")
      .required(&P::tau, "tau", D::Time, positive(), "relaxation time tau_i");
  return t;
}

// A layer's name and thickness: given, or layer<i> and (one layer) the block's length. With an
// imported geometry the layers are its groups: no thickness.
void readLayerExtent(Section& s, LayerSpec& L, std::size_t index, bool shorthand, double blockLength) {
  if (shorthand) {
    L.name = "tissue";
    L.thickness = blockLength;
    if (!s.has("material"))
      throw s.error("material", "", "is required: give tissue.material (one layer) or tissue.layers",
                    "a library name or a material section");
    return;
  }
  L.name = s.text("name");
  if (L.name.empty()) s.remember("name", L.name = fmt::format("layer{}", index + 1));
  if (blockLength > 0.0) {
    L.thickness = s.number("thickness");
  } else if (s.has("thickness")) {
    throw s.error("thickness", s.raw("thickness").Scalar(),
                  "has no meaning with tissue.geometry: the layers are the geometry's groups, by name",
                  "no thickness; a name that is a group of the geometry");
  }
}

LayerSpec readLayer(Section& s, std::size_t index, bool shorthand, double blockLength, const Scenario& sc) {
  LayerSpec L;
  readLayerExtent(s, L, index, shorthand, blockLength);
  layerTable().read(s, L, sc);  // material and the force sections
  return L;
}

// The layer's sections (read by the table: material, puncture, cutting, friction, interaction),
// the rows a one-layer tissue carries directly.
template <class T>
T& layerSections(T& t) {
  using L = LayerSpec;
  const auto sub = [](const char* key, auto table) {
    return [key, table](Section& s, L& l, const Scenario& sc) {
      Section sec = s.sub(key);
      table().read(sec, l, sc);
    };
  };
  return t
      .section("material", Kind::MaterialRef, "material", true, "",
               "a library name (e.g. gelatin_10wt) or a material section",
               [](Section& s, L& l, const Scenario& sc) { l.material = readMaterial(s, "material", sc); })
      .section("puncture", Kind::Section, "puncture", false, "", "puncture threshold; omitted = punctures on contact",
               sub("puncture", punctureTable))
      .section("cutting", Kind::Section, "cutting", false, "force: 0 N", "cutting at the tip", sub("cutting", cuttingTable))
      .section("friction", Kind::Section, "friction", false, "all zero", "friction along the shaft: the coefficients of the Karnopp law (C_p to static_band) and of the Coulomb "
               "law (coefficient); each engine applies one law (model.engine)",
               [](Section& s, L& l, const Scenario& sc) {
                 Section f = s.sub("friction");
                 frictionTable().read(f, l.friction, sc);
               })
      .section("interaction", Kind::Section, "interaction", false, "", "needle-tissue interaction parameters",
               sub("interaction", interactionTable));
}

ParamTable<LayerSpec> makeLayer() {
  using L = LayerSpec;
  ParamTable<L> t("layer");
  // name and thickness: readLayerExtent (their defaults depend on the layer's index and the block).
  t.text(&L::name, "name", "layer<i>", "label in results")
      .optional(&L::thickness, "thickness", D::Length, positive(),
                "thickness along the surface normal; layers must add up to block.length (required with a block; "
                "none with tissue.geometry, whose groups are the layers)")
      .docOnly(2);
  return layerSections(t);
}

// An inclusion that is a group of tissue.geometry: its elements give its place and size.
void readMeshInclusion(Section& s, InclusionSpec& I, const Scenario& sc) {
  for (const char* k : {"shape", "depth", "lateral", "elevation", "radius"})
    if (s.has(k))
      throw s.error(k, s.raw(k).IsScalar() ? s.raw(k).Scalar() : "",
                    "has no meaning for an inclusion that is a group of tissue.geometry (its elements are the inclusion)",
                    "no shape, depth, lateral, elevation or radius; or a name that is not a group of the geometry");
  I.shape = InclusionSpec::Shape::Mesh;
  I.material = readMaterial(s, "material", sc);
  // NaN: the layer around it, once the regions are known (tissue_geometry.cpp mapRegions)
  I.friction_coefficient = s.optNumber("friction").value_or(std::nan(""));
  I.toughness = s.optNumber("toughness").value_or(std::nan(""));
}

// A sphere or cylinder placed by its centre and radius.
void readPlacedInclusion(Section& s, InclusionSpec& I, const TissueSpec& T, const Scenario& sc) {
  I.shape = s.choice("shape") == "cylinder" ? InclusionSpec::Shape::Cylinder : InclusionSpec::Shape::Sphere;
  I.x = s.number("depth");
  I.y = s.number("lateral");
  I.z = s.number("elevation");
  I.radius = s.number("radius");
  if (I.shape == InclusionSpec::Shape::Cylinder && I.z != 0.0)
    throw s.error("elevation", "", "has no meaning for a cylinder (its axis runs through the block's height)",
                  "elevation for a sphere only");
  const bool inside = I.x - I.radius >= 0.0 && I.x + I.radius <= T.length && std::abs(I.y) + I.radius <= 0.5 * T.width &&
                      (I.shape == InclusionSpec::Shape::Cylinder || std::abs(I.z) + I.radius <= 0.5 * T.height);
  if (!inside)
    throw s.error("radius", fmt::format("{:g} mm", I.radius * 1e3),
                  fmt::format("puts the inclusion (centre at depth {:g} mm, lateral {:g} mm, elevation {:g} mm) "
                              "outside the {:g} x {:g} x {:g} mm block",
                              I.x * 1e3, I.y * 1e3, I.z * 1e3, T.length * 1e3, T.width * 1e3, T.height * 1e3),
                  "an inclusion inside the block");
  I.material = readMaterial(s, "material", sc);
  // Not given: the layer around it (in an imported geometry known once its regions are, mapRegions).
  const double nan = std::nan("");
  const LayerSpec* around = T.geometry ? nullptr : &T.layers[T.layerAt(I.x)];
  I.friction_coefficient = s.optNumber("friction").value_or(around ? around->friction.coefficient : nan);
  I.toughness = s.optNumber("toughness").value_or(around ? around->toughness : nan);
}

// An inclusion named like no group of the geometry and placed by no depth and radius.
void refuseUnplaced(Section& s, const InclusionSpec& I, const TissueSpec& T) {
  const auto names = groupNames(*T.geometry);
  const std::vector<std::string> groups(names.begin(), names.end());
  const std::string near = nearestName(I.name, groups);
  throw s.error("name", I.name,
                fmt::format("names no group of {}{}", T.geometry->file, near.empty() ? "" : " (did you mean '" + near + "'?)"),
                fmt::format("the name of a group of the geometry ({}); or a sphere or cylinder placed by depth and radius",
                            groups.empty() ? "it has no named groups" : "its groups: " + fmt::format("{}", fmt::join(groups, ", "))));
}

InclusionSpec readInclusion(Section& s, std::size_t index, const TissueSpec& T, const Scenario& sc) {
  InclusionSpec I;
  I.name = s.text("name");
  if (I.name.empty()) s.remember("name", I.name = fmt::format("inclusion{}", index + 1));
  const bool meshGroup = T.geometry && groupNames(*T.geometry).count(I.name);
  if (meshGroup) readMeshInclusion(s, I, sc);
  if (!meshGroup && T.geometry && !s.has("depth") && !s.has("radius")) refuseUnplaced(s, I, T);
  if (!meshGroup) {
    for (const char* k : {"depth", "radius"})
      if (!s.has(k))
        throw s.error(k, "", "is required but missing",
                      T.geometry ? "a length; or an inclusion name that is a group of tissue.geometry" : "a length");
    readPlacedInclusion(s, I, T, sc);
  }
  inclusionTable().read(s, I, sc);  // target, interface, interface_friction
  if (!I.sliding && I.interface_friction != 0.0)
    throw s.error("interface_friction", "", "applies to a sliding inclusion only", "interface: sliding");
  return I;
}

ParamTable<InclusionSpec> makeInclusion() {
  using I = InclusionSpec;
  ParamTable<I> t("inclusion");
  // Read by readInclusion: which of them apply depends on whether the inclusion is a group of the geometry.
  t.text(&I::name, "name", "inclusion<i>", "label in results")
      .choice(&I::shape, "shape", {{"sphere", I::Shape::Sphere}, {"cylinder", I::Shape::Cylinder}},
              "sphere, or cylinder (a vessel: axis out of the insertion plane, through the block's height)")
      .optional(&I::x, "depth", D::Length, nonNegative(),
                "centre: depth x from the entry face (required unless the inclusion is a group of tissue.geometry)")
      .quantity(&I::y, "lateral", D::Length, "mm", anyValue(),
                "centre: y across the width from the block's centre line (+ = the side a tilted needle goes to)")
      .quantity(&I::z, "elevation", D::Length, "mm", anyValue(),
                "centre: z across the height from the block's mid-plane (sphere only)")
      .optional(&I::radius, "radius", D::Length, positive(),
                "radius (required unless the inclusion is a group of tissue.geometry)")
      .section("material", Kind::MaterialRef, "material", true, "", "a library name or a material section")
      .row(numberDoc("inclusion", "friction", D::None, nonNegative(), "the surrounding layer's",
                     "Coulomb coefficient of needle contact inside it; not given: friction.coefficient of the layer "
                     "around it (the layer at its centre; a group of tissue.geometry: the layer its elements touch "
                     "most)"))
      .row(numberDoc("inclusion", "toughness", D::ForcePerLength, nonNegative(), "the surrounding layer's",
                     "rupture toughness G_c inside it; not given: interaction.toughness of the layer around it (as "
                     "friction)"))
      .docOnly(t.docs().size())
      .choice(&I::sliding, "interface", {{"bonded", false}, {"sliding", true}},
              "bonded (shares the tissue's material points or nodes) or sliding (a separate body in frictional "
              "contact with the tissue: mpm only)")
      .number(&I::interface_friction, "interface_friction", nonNegative(),
              "Coulomb coefficient between a sliding inclusion and the tissue")
      .flag(&I::target, "target", "the needle aims at it: its displacement is the targeting error");
  return t;
}

// tissue.block, or tissue.geometry (scenario/tissue_geometry.hpp) whose bounding box is the block.
void readBlockOrGeometry(Section& t, TissueSpec& T, const Scenario& sc) {
  if (t.has("block") == t.has("geometry"))
    throw t.error(t.has("block") ? "geometry" : "block", "",
                  t.has("block") ? "is given together with tissue.block" : "is required but missing",
                  "either block (a generated block) or geometry (an imported one)");
  if (t.has("geometry")) {
    Section g = t.sub("geometry");
    T.geometry = placeGeometry(g, sc.source, T);
    return;
  }
  Section b = t.sub("block");
  blockTable().read(b, T, sc);
}

// tissue.layers, or one layer's fields directly under tissue; with a block they fill its length.
void readLayers(Section& t, TissueSpec& T, const Scenario& sc) {
  const double blockLength = T.geometry ? 0.0 : T.length;
  auto layers = t.list("layers");
  if (layers.empty()) {
    T.layers.push_back(readLayer(t, 0, true, T.length, sc));
    return;
  }
  for (const char* k : {"material", "puncture", "cutting", "friction", "interaction"})
    if (t.has(k))
      throw t.error(k, "", "is given both here and in tissue.layers",
                    "either tissue.layers, or one layer's fields directly under tissue");
  for (std::size_t i = 0; i < layers.size(); ++i) {
    Section l = t.element(layers[i], "layers", i);
    T.layers.push_back(readLayer(l, i, false, blockLength, sc));
  }
  if (T.geometry) return;
  double sum = 0.0;
  for (const auto& L : T.layers) sum += L.thickness;
  if (std::abs(sum - T.length) > 1e-9 + 1e-6 * T.length)
    throw t.error("layers", fmt::format("{:g} mm in all", sum * 1e3),
                  fmt::format("the layer thicknesses must add up to block.length ({:g} mm)", T.length * 1e3),
                  "thicknesses that sum to block.length");
}

// tissue.inclusions; then an imported geometry's regions and held far side, and the friction and
// toughness an inclusion takes from the layer around it, recorded as values.
void readInclusions(Section& t, TissueSpec& T, const Scenario& sc) {
  auto inclusions = t.list("inclusions");
  for (std::size_t i = 0; i < inclusions.size(); ++i) {
    Section l = t.element(inclusions[i], "inclusions", i);
    T.inclusions.push_back(readInclusion(l, i, T, sc));
  }
  if (T.geometry) {
    auto geometry = std::make_shared<ImportedGeometry>(*T.geometry);
    mapRegions(*geometry, T, t);
    Section g = t.sub("geometry");
    markSupport(*geometry, g);
    T.geometry = geometry;
  }
  for (std::size_t i = 0; i < inclusions.size(); ++i) {
    Section l = t.element(inclusions[i], "inclusions", i);
    if (!l.has("friction")) l.rememberNumber("friction", T.inclusions[i].friction_coefficient);
    if (!l.has("toughness")) l.rememberNumber("toughness", T.inclusions[i].toughness);
  }
}

ParamTable<TissueSpec> makeTissue() {
  using T = TissueSpec;
  ParamTable<T> t("tissue");
  t.section("block", Kind::Section, "block", false, "", "block size (required unless tissue.geometry is given)",
            readBlockOrGeometry)
      .section("geometry", Kind::Section, "geometry", false, "",
               "an imported tissue geometry instead of the block: a Gmsh mesh or script, or closed surfaces meshed by "
               "Gmsh; its groups are the layers and inclusions, by name (engines explicit, mpm, realtime2d, realtime3d)")
      .section("layers", Kind::List, "layer", false, "",
               "layers from the entry face inwards; omit for one layer and write the layer's fields "
               "(material, puncture, cutting, friction, interaction) directly under tissue",
               readLayers)
      .section("inclusions", Kind::List, "inclusion", false, "",
               "bodies embedded in the block (a tumour to target, a vessel): engines mpm, explicit and realtime2d",
               readInclusions);
  // A one-layer tissue carries the layer's fields directly (read by readLayers).
  ParamTable<LayerSpec> shorthand("tissue");
  for (FieldDoc f : layerSections(shorthand).docs()) {
    f.required = false;
    f.help += " (one-layer shorthand)";
    t.row(std::move(f));
  }
  return t;
}

// The rows of tissue.geometry; tissue_geometry.cpp reads them.
ParamTable<ImportedGeometry> makeGeometry() {
  ParamTable<ImportedGeometry> t("geometry");
  FieldDoc unit = t.otherDoc("unit", Kind::Choice, "", "length unit of the file's coordinates");
  unit.required = true;
  unit.choices = {"m", "cm", "mm", "um"};
  t.row(t.otherDoc("file", Kind::String, "",
                   "a Gmsh mesh (.msh, format 2 or 4, ASCII or binary) or script (.geo), or one closed surface (.stl, "
                   ".ply, .vtk, .off, .obj); relative to the scenario file"))
      .section("surfaces", Kind::List, "surface", false, "", "several closed surfaces (instead of file), one body each")
      .row(std::move(unit))
      .section("translate", Kind::Section, "offset", false, "0 mm", "placement: shift after the rotation")
      .section("rotate", Kind::Section, "rotation", false, "0 deg",
               "placement: rotations about the tissue frame's x, then y, then z axis, before the shift")
      .row(numberDoc("geometry", "element_size", D::Length, positive(),
                     "surfaces: 1/20 of the first one's bounding-box diagonal; a script: its own sizes",
                     "size of the elements Gmsh makes from surfaces or a .geo script"))
      .row(numberDoc("geometry", "support_depth", D::Length, positive(), "20 % of the body's depth",
                     "the boundary facing away from the needle within this depth of the deepest point is held fixed"));
  FieldDoc maxElements = numberDoc("geometry", "max_elements", D::None, closed(1.0, 1e9), "2e6",
                                   "refuse a geometry that holds or would make more elements (estimated before meshing "
                                   "from the volume and the largest element size); raise it to allow a finer mesh");
  maxElements.whole = true;
  t.row(std::move(maxElements))
      .row(numberDoc("geometry", "max_mesh_time", D::Time, positive(), "120 s",
                     "reading and meshing the geometry is stopped and refused after this long (wall clock and CPU "
                     "time)"))
      .row(numberDoc("geometry", "max_mesh_memory_mib", D::None, closed(64.0, 1e7), "4096",
                     "memory (MiB) reading and meshing the geometry may take; more is refused"));
  return t;
}

ParamTable<ImportedGeometry> makeSurface() {
  ParamTable<ImportedGeometry> t("surface");
  FieldDoc file = t.otherDoc("file", Kind::String, "", "a closed surface (.stl, .ply, .vtk, .off, .obj); relative to the scenario file");
  file.required = true;
  t.row(std::move(file))
      .row(t.otherDoc("body", Kind::String, "the file's stem", "name of the body it bounds: a layer or inclusion name"));
  return t;
}

ParamTable<Placement> makePlacement(bool rotation) {
  ParamTable<Placement> t(rotation ? "rotation" : "offset");
  for (auto [member, axis] : {std::pair{&Placement::x, "x"}, std::pair{&Placement::y, "y"}, std::pair{&Placement::z, "z"}}) {
    if (rotation)
      t.quantity(member, axis, D::Angle, "deg", closed(-2 * std::numbers::pi, 2 * std::numbers::pi),
                 std::string("rotation about the tissue frame's ") + axis + " axis (right hand)");
    else
      t.quantity(member, axis, D::Length, "mm", anyValue(), std::string("shift along ") + axis);
  }
  return t;
}

}  // namespace

const ParamTable<TissueSpec>& tissueTable() {
  static const auto t = makeTissue();
  return t;
}
const ParamTable<LayerSpec>& layerTable() {
  static const auto t = makeLayer();
  return t;
}
const ParamTable<materials::MaterialSpec>& materialTable() {
  static const auto t = makeMaterial();
  return t;
}
const ParamTable<materials::PronyTerm>& pronyTable() {
  static const auto t = makeProny();
  return t;
}
const ParamTable<InclusionSpec>& inclusionTable() {
  static const auto t = makeInclusion();
  return t;
}
const ParamTable<ImportedGeometry>& geometryTable() {
  static const auto t = makeGeometry();
  return t;
}
const ParamTable<ImportedGeometry>& surfaceTable() {
  static const auto t = makeSurface();
  return t;
}
const ParamTable<Placement>& offsetTable() {
  static const auto t = makePlacement(false);
  return t;
}
const ParamTable<Placement>& rotationTable() {
  static const auto t = makePlacement(true);
  return t;
}

}  // namespace needlesim::scenario
