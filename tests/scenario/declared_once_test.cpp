// Each scenario field declared once: the schema (and docs/scenario-format.md, generated from it),
// the scenario as understood (summary.json's "scenario") and the structs agree on the fields and
// their defaults; every default is recorded as a value; a field an engine does not use gets a note.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>

#include "needlesim/engines/engine.hpp"
#include "needlesim/engines/memory_sink.hpp"
#include "needlesim/engines/run_scenario.hpp"
#include "needlesim/scenario/mesh_file.hpp"
#include "needlesim/scenario/model_section.hpp"
#include "needlesim/scenario/problem_sections.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/scenario/schema.hpp"
#include "needlesim/scenario/study_section.hpp"

using namespace needlesim;
using scenario::FieldDoc;
using scenario::Kind;

namespace {

std::string exampleText(const std::string& rel) {
  std::ifstream in(std::string(NEEDLESIM_SOURCE_DIR) + "/" + rel);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// Defaults that depend on data the reader does not have a single value for, each for a reason
// written in the schema: the engine computes them (curvature from the beam-on-foundation tip
// loads), or they differ per layer (the cohesive fracture energy: each layer's toughness), or
// they are alternatives rather than defaults (an element size instead of node counts), or the
// run decides them (the scenario's name and results folder: the file's name, --out).
const std::set<std::string> kNoSingleValue{"scenario.name", "output.directory", "steering.curvature",
                                           "explicit_cohesive.fracture_energy", "realtime2d.element_size",
                                           "realtime3d.curvature"};

double siOf(const nlohmann::json& v) {
  return v.is_number() ? v.get<double>() : units::parse(v.get<std::string>()).value;
}

// Walks the record of section type `type` against the schema: every key recorded is a field,
// every field with a default is recorded, with the schema's default when that is a value.
void compare(const nlohmann::json& record, const std::string& type, const std::string& path, const Scenario& sc,
             std::set<std::string>& seen) {
  for (const auto& [key, value] : record.items()) {
    const FieldDoc* f = scenario::findField(type, key);
    ASSERT_NE(f, nullptr) << path << key << " is recorded but section '" << type << "' has no such field";
    seen.insert(type + "." + key);
    if (f->kind == Kind::Section && value.is_object()) compare(value, f->child, path + key + ".", sc, seen);
    if (f->kind == Kind::MaterialRef && value.is_object()) compare(value, "material", path + key + ".", sc, seen);
    if (f->kind == Kind::List)
      for (std::size_t i = 0; i < value.size(); ++i)
        if (value[i].is_object()) compare(value[i], f->child, fmt::format("{}{}[{}].", path, key, i), sc, seen);
  }
  for (const FieldDoc* f : scenario::fieldsOf(type)) {
    if (f->default_text.empty() || f->kind == Kind::Section || f->kind == Kind::List) continue;
    if (kNoSingleValue.count(type + "." + f->key)) continue;
    if (type == "geometry" && f->key == "element_size" && record.contains("file") &&
        scenario::isGmshMeshOrScript(record["file"].get<std::string>()))
      continue;  // a mesh has its elements, a script its own sizes: no element size is used
    if (type == "inclusion" && !record.contains("radius") &&
        (f->key == "shape" || f->key == "lateral" || f->key == "elevation"))
      continue;  // an inclusion that is a group of tissue.geometry has no shape or centre to give
    ASSERT_TRUE(record.contains(f->key)) << path << f->key << " has the default '" << f->default_text
                                         << "' in the schema but is not recorded";
    if ((f->kind != Kind::Quantity && f->kind != Kind::Number) || sc.given_at.count(path + f->key)) continue;
    double schemaDefault = 0.0;
    try {
      schemaDefault = units::parse(f->default_text).value;
    } catch (const std::invalid_argument&) {
      continue;  // a formula: recorded as the value it gives (checked above)
    }
    if (record[f->key].is_string() || record[f->key].is_number())
      EXPECT_EQ(siOf(record[f->key]), schemaDefault) << path << f->key << " (schema default " << f->default_text << ")";
  }
}

}  // namespace

TEST(DeclaredOnce, SchemaAndUnderstoodListTheSameFieldsWithTheSameDefaults) {
  // Scenarios that give nothing of the model sections: every field there is a default.
  std::set<std::string> seen;
  for (const char* file : {"examples/gelatin_18G_3mms.yaml", "examples/realtime2d/layered_target.yaml"}) {
    const Scenario sc = scenario::readText(exampleText(file), file);
    const auto record = nlohmann::json::parse(sc.understood);
    SCOPED_TRACE(file);
    compare(record, "scenario", "", sc, seen);
  }
  // Every field of every engine's section is recorded (none is left to the engine).
  for (const scenario::ModelSection* m : scenario::modelSections())
    for (const auto& f : m->docs())
      if (f.section == m->key && !f.default_text.empty() && f.kind != Kind::List &&
          !kNoSingleValue.count(f.section + "." + f.key))
        EXPECT_TRUE(seen.count(f.section + "." + f.key)) << "model." << m->key << "." << f.key << " is not recorded";
}

TEST(DeclaredOnce, TheDocsListEveryFieldOfTheSchemaWithItsDefault) {
  std::ifstream in(std::string(NEEDLESIM_SOURCE_DIR) + "/docs/scenario-format.md");
  const std::string doc((std::istreambuf_iterator<char>(in)), {});
  for (const auto& f : scenario::schema())
    EXPECT_NE(doc.find("| `" + f.key + "` | "), std::string::npos) << f.section << "." << f.key;
  EXPECT_NE(doc.find(scenario::schemaMarkdown()), std::string::npos)
      << "docs/scenario-format.md is out of date: regenerate its Reference part with `needlesim schema --markdown`";
}

TEST(DeclaredOnce, FormulaDefaultsAreRecordedAsValues) {
  const Scenario sc = scenario::defaultScenario();
  const auto r = nlohmann::json::parse(sc.understood);
  const auto& fr = r["tissue"]["friction"];
  const auto& f = sc.tissue.layers[0].friction;
  EXPECT_EQ(siOf(fr["C_n"]), f.C_p);
  EXPECT_EQ(siOf(fr["b_n"]), f.b_p);
  EXPECT_EQ(siOf(fr["D_p"]), f.C_p + f.b_p * f.static_band / 2);
  EXPECT_EQ(siOf(fr["D_n"]), f.C_n + f.b_n * f.static_band / 2);
  EXPECT_EQ(siOf(r["needle"]["inner_diameter"]), sc.needle.inner_diameter);
  EXPECT_GT(sc.needle.inner_diameter, 0.0);  // 18 G: from the gauge table
  EXPECT_EQ(siOf(r["model"]["mpm"]["particle_spacing"]), 0.5 * sc.model.mpm.grid_spacing);
  EXPECT_EQ(siOf(r["model"]["realtime2d"]["tip_load_ratio"]), 1.0 / std::tan(sc.needle.bevel_angle));
  EXPECT_EQ(siOf(r["model"]["steering"]["tear_length"]), sc.needle.outer_diameter / 2);
  EXPECT_EQ(r["model"]["explicit"]["element"], "quad4");
  EXPECT_GT(siOf(r["model"]["explicit"]["field_interval"]), 0.0);
}

TEST(DeclaredOnce, StructDefaultsAreTheSchemaDefaults) {
  const NeedleSpec n;
  EXPECT_EQ(n.bevel_angle, units::parse(scenario::field("needle", "bevel_angle").default_text).value);
  EXPECT_EQ(n.youngs_modulus, units::parse(scenario::field("needle", "youngs_modulus").default_text).value);
  EXPECT_EQ(n.density, units::parse(scenario::field("needle", "density").default_text).value);
  EXPECT_EQ(n.poisson, units::parse(scenario::field("needle", "poisson").default_text).value);
  const InsertionSpec ins;
  EXPECT_EQ(ins.entry_angle, units::parse(scenario::field("insertion", "entry_angle").default_text).value);
  EXPECT_EQ(ins.entry_offset, units::parse(scenario::field("insertion", "entry_offset").default_text).value);
  const OutputSpec o;
  EXPECT_EQ(o.checkpoint_interval, units::parse(scenario::field("output", "checkpoint_interval").default_text).value);
  EXPECT_EQ(o.max_steps, units::parse(scenario::field("output", "max_steps").default_text).value);
  EXPECT_EQ(MotionSegment{}.duty_cycle, units::parse(scenario::field("insert", "duty_cycle").default_text).value);
  EXPECT_EQ(ModelSpec{}.time_step, units::parse(scenario::field("model", "time_step").default_text).value);
  EXPECT_EQ(ModelSpec{}.engine, scenario::field("model", "engine").default_text);
  EXPECT_EQ(LayerSpec{}.cutting_force, units::parse(scenario::field("cutting", "force").default_text).value);
  EXPECT_EQ(ExplicitModelSpec{}.cfl, units::parse(scenario::field("explicit", "cfl").default_text).value);
  EXPECT_EQ(MpmModelSpec{}.grid_spacing, units::parse(scenario::field("mpm", "grid_spacing").default_text).value);
}

// The schema rows of section `type` are the rows of its table, in order.
template <class Spec>
void expectSchemaIsTable(const scenario::ParamTable<Spec>& table) {
  const auto rows = table.docs();
  const auto schema = scenario::fieldsOf(table.type());
  ASSERT_EQ(rows.size(), schema.size()) << table.type();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    SCOPED_TRACE(table.type() + "." + rows[i].key);
    EXPECT_EQ(schema[i]->key, rows[i].key);
    EXPECT_EQ(schema[i]->default_text, rows[i].default_text);
    EXPECT_EQ(schema[i]->rangeText(), rows[i].rangeText());
    EXPECT_EQ(schema[i]->required, rows[i].required);
    EXPECT_EQ(schema[i]->help, rows[i].help);
  }
}

TEST(DeclaredOnce, BlockNeedleInsertionModelOutputAndForceSectionsAreTheirTables) {
  expectSchemaIsTable(scenario::blockTable());
  expectSchemaIsTable(scenario::needleTable());
  expectSchemaIsTable(scenario::insertionTable());
  expectSchemaIsTable(scenario::segmentTable());
  for (const char* kind : {"insert", "retract", "pause", "rotate"}) expectSchemaIsTable(scenario::segmentKindTable(kind));
  expectSchemaIsTable(scenario::outputTable());
  // model: engine and time_step from the table, then one row per engine's section
  const auto model = scenario::modelTable().docs();
  ASSERT_EQ(model.size(), 2u);
  EXPECT_EQ(scenario::fieldsOf("model").at(0)->key, model[0].key);
  EXPECT_EQ(scenario::fieldsOf("model").at(1)->default_text, model[1].default_text);
  expectSchemaIsTable(scenario::frictionTable());
  expectSchemaIsTable(scenario::punctureTable());
  expectSchemaIsTable(scenario::cuttingTable());
  expectSchemaIsTable(scenario::interactionTable());
}

TEST(DeclaredOnce, TopLevelTissueLayersMaterialsInclusionsGeometryAndUnitsAreTheirTables) {
  expectSchemaIsTable(scenario::scenarioTable());
  expectSchemaIsTable(scenario::tissueTable());
  expectSchemaIsTable(scenario::layerTable());
  expectSchemaIsTable(scenario::materialTable());
  expectSchemaIsTable(scenario::pronyTable());
  expectSchemaIsTable(scenario::inclusionTable());
  expectSchemaIsTable(scenario::geometryTable());
  expectSchemaIsTable(scenario::surfaceTable());
  expectSchemaIsTable(scenario::offsetTable());
  expectSchemaIsTable(scenario::rotationTable());
  expectSchemaIsTable(scenario::unitsTable());
  // Every section type of a scenario, and of a study file, comes from a table.
  std::set<std::string> tables;
  for (const auto& f : scenario::schema()) tables.insert(f.section);
  std::size_t rows = 0;
  for (const auto& type : tables) rows += scenario::fieldsOf(type).size();
  std::size_t declared = 0;
  for (const auto& docs :
       {scenario::scenarioTable().docs(), scenario::tissueTable().docs(), scenario::blockTable().docs(),
        scenario::layerTable().docs(), scenario::materialTable().docs(), scenario::pronyTable().docs(),
        scenario::inclusionTable().docs(), scenario::geometryTable().docs(), scenario::surfaceTable().docs(),
        scenario::offsetTable().docs(), scenario::rotationTable().docs(), scenario::punctureTable().docs(),
        scenario::cuttingTable().docs(), scenario::frictionTable().docs(), scenario::interactionTable().docs(),
        scenario::needleTable().docs(), scenario::insertionTable().docs(), scenario::segmentTable().docs(),
        scenario::modelTable().docs(), scenario::outputTable().docs(), scenario::unitsTable().docs()})
    declared += docs.size();
  for (const char* kind : {"insert", "retract", "pause", "rotate"}) declared += scenario::segmentKindTable(kind).docs().size();
  for (const scenario::ModelSection* m : scenario::modelSections()) declared += 1 + m->docs().size();
  declared += scenario::planDocs().size();  // the plan, plan_avoid and plan_uncertainty tables (plan_section.cpp)
  declared += scenario::studyFileTable().docs().size() + scenario::studyParameterTable().docs().size();
  EXPECT_EQ(declared, rows) << "a section's rows are written outside its table";
}

TEST(DeclaredOnce, InclusionMaterialAndPlacementStructDefaultsAreTheSchemaDefaults) {
  const InclusionSpec i;
  EXPECT_EQ(i.y, units::parse(scenario::field("inclusion", "lateral").default_text).value);
  EXPECT_EQ(i.z, units::parse(scenario::field("inclusion", "elevation").default_text).value);
  EXPECT_EQ(i.interface_friction, units::parse(scenario::field("inclusion", "interface_friction").default_text).value);
  EXPECT_EQ(i.sliding ? "sliding" : "bonded", scenario::field("inclusion", "interface").default_text);
  EXPECT_EQ(i.target ? "true" : "false", scenario::field("inclusion", "target").default_text);
  EXPECT_EQ(i.shape == InclusionSpec::Shape::Sphere ? "sphere" : "cylinder", scenario::field("inclusion", "shape").default_text);
  const materials::MaterialSpec m;
  EXPECT_EQ(m.density, units::parse(scenario::field("material", "density").default_text).value);
  EXPECT_EQ(m.name, scenario::field("material", "name").default_text);
  EXPECT_EQ(scenario::Placement{}.x, units::parse(scenario::field("offset", "x").default_text).value);
  EXPECT_EQ(scenario::Placement{}.z, units::parse(scenario::field("rotation", "z").default_text).value);
}

TEST(DeclaredOnce, AGaugeGivesTheBoreAndALengthASolidNeedle) {
  std::string yaml = exampleText("examples/gelatin_18G_3mms.yaml");
  const Scenario gauge = scenario::readText(yaml, "gauge.yaml");
  EXPECT_EQ(gauge.needle.outer_diameter, units::gaugeSize(18)->outer);
  EXPECT_EQ(gauge.needle.inner_diameter, units::gaugeSize(18)->inner);
  const auto at = yaml.find("outer_diameter: 18 G");
  ASSERT_NE(at, std::string::npos);
  yaml.replace(at, 20, "outer_diameter: 1.27 mm");
  const Scenario length = scenario::readText(yaml, "length.yaml");
  EXPECT_EQ(length.needle.outer_diameter, 1.27e-3);
  EXPECT_EQ(length.needle.inner_diameter, 0.0);
  EXPECT_EQ(siOf(nlohmann::json::parse(length.understood)["needle"]["inner_diameter"]), 0.0);
}

TEST(DeclaredOnce, AScenarioGivingOnlyWhatIsRequiredGetsTheStructDefaults) {
  // Every optional field of the needle, insertion, its segments, output and a layer's forces left out.
  const std::string yaml = R"(tissue:
  block: {length: 50 mm, width: 50 mm, height: 50 mm}
  material: gelatin_10wt
needle: {outer_diameter: 1 mm, length: 100 mm}
insertion:
  profile:
    - insert: {to: 20 mm, speed: 1 mm/s}
    - rotate: {by: 90 deg, rate: 90 deg/s}
    - pause: {duration: 1 s}
    - retract: {to: 0 mm, speed: 1 mm/s}
)";
  const Scenario sc = scenario::readText(yaml, "required_only.yaml");
  const NeedleSpec n;
  EXPECT_EQ(sc.needle.inner_diameter, 0.0);  // no gauge: solid
  EXPECT_EQ(sc.needle.bevel_angle, n.bevel_angle);
  EXPECT_EQ(sc.needle.tip, n.tip);
  EXPECT_EQ(sc.needle.youngs_modulus, n.youngs_modulus);
  EXPECT_EQ(sc.needle.poisson, n.poisson);
  EXPECT_EQ(sc.needle.density, n.density);
  const InsertionSpec ins;
  EXPECT_EQ(sc.insertion.entry_angle, ins.entry_angle);
  EXPECT_EQ(sc.insertion.entry_offset, ins.entry_offset);
  EXPECT_EQ(sc.insertion.start_depth, ins.start_depth);
  EXPECT_EQ(sc.insertion.bevel_orientation, ins.bevel_orientation);
  const MotionSegment m;
  ASSERT_EQ(sc.insertion.segments.size(), 4u);
  EXPECT_EQ(sc.insertion.segments[0].rate, m.rate);
  EXPECT_EQ(sc.insertion.segments[0].duty_cycle, m.duty_cycle);
  EXPECT_EQ(sc.insertion.segments[1].axial, m.axial);
  EXPECT_EQ(sc.insertion.segments[1].duration, 1.0);  // 90 deg at 90 deg/s
  EXPECT_EQ(sc.model.engine, ModelSpec{}.engine);
  EXPECT_EQ(sc.model.time_step, ModelSpec{}.time_step);
  const OutputSpec o;
  EXPECT_EQ(sc.output.directory, o.directory);
  EXPECT_EQ(sc.output.interval, o.interval);
  EXPECT_EQ(sc.output.checkpoint_interval, o.checkpoint_interval);
  EXPECT_EQ(sc.output.max_steps, o.max_steps);
  EXPECT_EQ(sc.output.csv, o.csv);
  EXPECT_EQ(sc.output.html, o.html);
  const LayerSpec l;
  const LayerSpec& got = sc.tissue.layers.at(0);
  EXPECT_EQ(got.puncture_force, l.puncture_force);
  EXPECT_EQ(got.puncture_depth, l.puncture_depth);
  EXPECT_EQ(got.cutting_force, l.cutting_force);
  EXPECT_EQ(got.interaction_stiffness, l.interaction_stiffness);
  EXPECT_EQ(got.toughness, l.toughness);
  EXPECT_EQ(got.friction.C_p, l.friction.C_p);
  EXPECT_EQ(got.friction.coefficient, l.friction.coefficient);
  // The scenario's Karnopp band is the schema's (the struct keeps 0 for friction built in code).
  EXPECT_EQ(got.friction.static_band, units::parse(scenario::field("friction", "static_band").default_text).value);
  // Schema, record and struct agree on every field of these sections (walks the record).
  std::set<std::string> seen;
  compare(nlohmann::json::parse(sc.understood), "scenario", "", sc, seen);
  for (const char* f : {"rotate.axis", "insert.duty_cycle", "insert.spin_rate", "output.max_steps",
                        "output.checkpoint_interval", "needle.inner_diameter", "friction.D_n", "cutting.force"})
    EXPECT_TRUE(seen.count(f)) << f << " is not recorded";
}

TEST(DeclaredOnce, APunctureDepthIsItsOwnField) {
  std::string yaml = exampleText("examples/gelatin_18G_3mms.yaml");
  const auto at = yaml.find("puncture:");
  ASSERT_NE(at, std::string::npos);
  const auto end = yaml.find('\n', at);
  yaml.replace(at, end - at, "puncture: {depth: 4 mm}");
  const Scenario sc = scenario::readText(yaml, "depth.yaml");
  EXPECT_EQ(sc.tissue.layers[0].puncture_depth, 4e-3);
  EXPECT_EQ(sc.tissue.layers[0].puncture_force, 0.0);
  // The lumped engine turns it into a force; mpm says once that it does not use it.
  const MemorySink lumped = runInMemory(sc, RunOptions{false});
  EXPECT_GT(lumped.results.at("peak_force").value, 0.0);
  Scenario mpm = sc;
  mpm.model.engine = "mpm";
  const auto notes = unusedFieldNotes(*findEngine("mpm"), mpm);
  bool named = false;
  for (const auto& n : notes) named = named || n.find("tissue.puncture.depth") != std::string::npos;
  EXPECT_TRUE(named) << notes.size() << " notes";
}

TEST(DeclaredOnce, EveryEngineNotesEachGivenFieldItDoesNotUseOnce) {
  const Scenario sc = scenario::defaultScenario();  // gives puncture, cutting, C_p, b_p, static_band
  ASSERT_GT(sc.given_at.count("tissue.friction.C_p"), 0u);
  for (const auto& e : engineRegistry()) {
    const auto notes = unusedFieldNotes(e, sc);
    const bool karnopp = e.friction == FrictionLaw::Karnopp;
    int cp = 0;
    for (const auto& n : notes) cp += n.find("tissue.friction.C_p given but not used by engine " + e.name) == 0;
    EXPECT_EQ(cp, karnopp ? 0 : 1) << e.name;
  }
  // friction.coefficient given: the lumped and real-time engines do not use it.
  std::string yaml = exampleText("examples/gelatin_18G_3mms.yaml");
  const auto at = yaml.find("friction:");
  ASSERT_NE(at, std::string::npos);
  yaml.insert(yaml.find('\n', at), "\n    coefficient: 0.3");
  const Scenario coulomb = scenario::readText(yaml, "coulomb.yaml");
  const MemorySink sink = runInMemory(coulomb, RunOptions{false});
  int noted = 0;
  for (const auto& n : sink.notes) noted += n.find("tissue.friction.coefficient given but not used by engine lumped") == 0;
  EXPECT_EQ(noted, 1);
}

TEST(DeclaredOnce, EachEngineAppliesOneNamedFrictionLawAndUsesOnlyItsFields) {
  const std::vector<std::string> karnopp = frictionFields(FrictionLaw::Karnopp);
  const std::vector<std::string> coulomb = frictionFields(FrictionLaw::Coulomb);
  for (const auto& e : engineRegistry()) {
    SCOPED_TRACE(e.name);
    EXPECT_NE(e.friction, FrictionLaw::None);
    const auto& own = e.friction == FrictionLaw::Karnopp ? karnopp : coulomb;
    const auto& other = e.friction == FrictionLaw::Karnopp ? coulomb : karnopp;
    for (const auto& f : own) EXPECT_TRUE(e.usesField(f)) << f;
    for (const auto& f : other) EXPECT_FALSE(e.usesField(f)) << f;
    // The registration's own list names no friction field: the law says which.
    for (const auto& f : e.uses) EXPECT_FALSE(f.starts_with("friction.")) << f;
  }
  EXPECT_EQ(findEngine("lumped")->friction, FrictionLaw::Karnopp);
  EXPECT_EQ(findEngine("realtime3d")->friction, FrictionLaw::Karnopp);
  EXPECT_EQ(findEngine("explicit")->friction, FrictionLaw::Coulomb);
  EXPECT_EQ(findEngine("mpm")->friction, FrictionLaw::Coulomb);
  // The schema says which law each friction field belongs to, and each engine's law.
  for (const auto* f : scenario::fieldsOf("friction"))
    EXPECT_TRUE(f->help.starts_with(f->key == "coefficient" ? "Coulomb law" : "Karnopp law")) << f->key;
  EXPECT_NE(scenario::field("model", "engine").help.find("lumped insertion-force model (seed 003 section 3.2) (friction: Karnopp)"),
            std::string::npos);
}

TEST(DeclaredOnce, AnInclusionTakesTheFrictionOfTheLayerAroundIt) {
  // a 20 x 20 mm square: skin (depth 0-10 mm) and gel (10-20 mm); a sphere placed in the gel
  const auto dir = std::filesystem::temp_directory_path() / "needlesim_declared_once";
  std::filesystem::create_directories(dir);
  const auto mesh = dir / "two_layers.msh";
  std::ofstream(mesh) << R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "skin"
2 2 "gel"
$EndPhysicalNames
$Nodes
6
1 0 -10 0
2 10 -10 0
3 20 -10 0
4 20 10 0
5 10 10 0
6 0 10 0
$EndNodes
$Elements
4
1 2 2 1 1 1 2 5
2 2 2 1 1 1 5 6
3 2 2 2 2 2 3 4
4 2 2 2 2 2 4 5
$EndElements
)";
  const std::string yaml = R"(name: around
tissue:
  geometry: {file: )" + mesh.string() + R"(, unit: mm}
  layers:
    - {name: skin, material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45}, friction: {coefficient: 0.1}}
    - {name: gel, material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45}, friction: {coefficient: 0.4}}
  inclusions:
    - {name: lump, shape: cylinder, depth: 15 mm, radius: 2 mm, material: {law: neo-hookean, C10: 16.6 kPa, nu: 0.45}}
needle: {outer_diameter: 2 mm, length: 40 mm}
insertion:
  profile:
    - insert: {to: 5 mm, speed: 10 mm/s}
model: {engine: explicit, explicit: {dimension: 2d}}
)";
  const Scenario sc = scenario::readText(yaml, "around.yaml");
  EXPECT_EQ(sc.tissue.inclusions[0].friction_coefficient, 0.4);  // the gel's, not layer 0's
  EXPECT_EQ(nlohmann::json::parse(sc.understood)["tissue"]["inclusions"][0]["friction"], 0.4);
}

TEST(DeclaredOnce, TheStudyFileAndItsParametersAreTheirTables) {
  expectSchemaIsTable(scenario::studyFileTable());
  expectSchemaIsTable(scenario::studyParameterTable());
  // The struct's defaults are the schema's (read by the same table).
  const study::StudySpec spec;
  EXPECT_EQ(std::to_string(spec.samples), scenario::field("study", "samples").default_text);
  EXPECT_EQ(std::to_string(spec.seed), scenario::field("study", "seed").default_text);
  EXPECT_EQ(std::to_string(spec.parallel), scenario::field("study", "parallel").default_text);
  EXPECT_EQ(scenario::field("study", "method").default_text, "grid");
  EXPECT_EQ(spec.method, study::Method::Grid);
}

namespace {
// Rows whose default is a formula of other fields or of the data ("C_p", "grid_spacing / 2",
// "20 % of the body's depth"): a number or quantity whose default text is no value.
std::vector<const FieldDoc*> formulaDefaults() {
  std::vector<const FieldDoc*> out;
  for (const auto& f : scenario::schema()) {
    if ((f.kind != Kind::Quantity && f.kind != Kind::Number) || f.default_text.empty()) continue;
    try {
      units::parse(f.default_text);
    } catch (const std::invalid_argument&) {
      out.push_back(&f);
    }
  }
  return out;
}
}  // namespace

// A scenario whose tissue is a 20 mm cube given as a closed surface, meshed at the default size.
std::string cubeScenario() {
  const auto dir = std::filesystem::temp_directory_path() / "needlesim_declared_once";
  std::filesystem::create_directories(dir);
  std::ofstream off(dir / "cube.off");
  off << "OFF\n8 12 0\n";
  for (int i = 0; i < 8; ++i) off << 20 * (i & 1) << " " << 20 * ((i >> 1) & 1) - 10 << " " << 20 * (i >> 2) - 10 << "\n";
  // two outward triangles per face
  for (const char* f : {"0 2 1", "1 2 3", "4 5 6", "5 7 6", "0 1 4", "1 5 4", "2 6 3", "3 6 7", "0 4 2", "2 4 6",
                        "1 3 5", "3 7 5"})
    off << "3 " << f << "\n";
  return "tissue:\n  geometry: {surfaces: [{file: " + (dir / "cube.off").string() + R"(}], unit: mm}
  layers:
    - {name: cube, material: {law: neo-hookean, C10: 2 kPa, nu: 0.45}, friction: {coefficient: 0.2}}
needle: {outer_diameter: 18 G, length: 100 mm}
insertion:
  profile:
    - insert: {to: 10 mm, speed: 10 mm/s}
model: {engine: mpm}
)";
}

TEST(DeclaredOnce, EveryFormulaDefaultIsRecordedAsTheValueUsed) {
  // Scenarios that reach every section with a formula default and leave it out: the built-in
  // default, a layered one with inclusions, a Gmsh script, a plan, and a closed surface meshed
  // at the default element size.
  const std::string dir = std::string(NEEDLESIM_SOURCE_DIR) + "/examples/";
  const std::vector<Scenario> scenarios{
      scenario::defaultScenario(), scenario::readFile(dir + "realtime2d/layered_target.yaml"),
      scenario::readFile(dir + "realtime2d/imported_block.yaml"), scenario::readFile(dir + "planning/gel_block.yaml"),
      scenario::readText(cubeScenario(), "cube.yaml")};
  std::set<std::string> seen;
  for (const Scenario& sc : scenarios) {
    SCOPED_TRACE(sc.source);
    compare(nlohmann::json::parse(sc.understood), "scenario", "", sc, seen);
  }
  const auto formulas = formulaDefaults();
  EXPECT_GE(formulas.size(), 12u);  // C_n, b_n, D_p, D_n, inner_diameter, support_depth, element_size, ...
  for (const FieldDoc* f : formulas) {
    const std::string row = f->section + "." + f->key;
    if (kNoSingleValue.count(row)) continue;
    EXPECT_TRUE(seen.count(row)) << row << " (default '" << f->default_text << "') is not recorded as a value";
  }
  // The values used: 20 % of the geometry's depth; 1/20 of the cube's bounding-box diagonal.
  const Scenario& script = scenarios[2];
  const auto geo = nlohmann::json::parse(script.understood)["tissue"]["geometry"];
  EXPECT_EQ(siOf(geo["support_depth"]), 0.2 * (script.tissue.geometry->hi[0] - script.tissue.geometry->lo[0]));
  EXPECT_FALSE(geo.contains("element_size"));  // a script meshes at its own sizes
  const Scenario& cube = scenarios[4];
  const auto surface = nlohmann::json::parse(cube.understood)["tissue"]["geometry"];
  EXPECT_NEAR(siOf(surface["element_size"]), 0.02 * std::sqrt(3.0) / 20, 1e-12);
  EXPECT_NEAR(siOf(surface["support_depth"]), 0.2 * 0.02, 1e-12);
  EXPECT_EQ(surface["surfaces"][0]["body"], "cube");
  // Read back, the recorded values give the same geometry.
  const Scenario again = scenario::readText(cube.understood, "cube_again.yaml");
  EXPECT_EQ(again.tissue.geometry->mesh->elements(), cube.tissue.geometry->mesh->elements());
  EXPECT_EQ(again.understood, cube.understood);
}

TEST(DeclaredOnce, AnEngineKeepsItsSettingsInTheModelsStoreWithoutAMember) {
  struct Settings {
    double stiffness = 3.0;
  };
  Scenario sc;
  EXPECT_EQ(std::as_const(sc).model.spec<Settings>().stiffness, 3.0);  // not read: the defaults
  sc.model.spec<Settings>().stiffness = 5.0;
  const Scenario copy = sc;
  sc.model.spec<Settings>().stiffness = 7.0;
  EXPECT_EQ(copy.model.spec<Settings>().stiffness, 5.0);  // a copy of the scenario holds its own
  EXPECT_EQ(std::as_const(sc).model.spec<Settings>().stiffness, 7.0);
}
