#pragma once
// Every section of a scenario as a table, each field declared once (scenario/parameter_table.hpp):
// the schema, the reader and the scenario as understood take these tables. The top level
// (reader.cpp); the block, needle, insertion, model (engine, time step), output and a layer's force
// sections (problem_sections.cpp); the tissue, layers, materials, inclusions and an imported
// geometry (tissue_sections.cpp). Each engine's model.<engine> is its own (model_section.hpp).
// Internal to the scenario reader.
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::scenario {

// The top level: name, description and the sections.
const ParamTable<Scenario>& scenarioTable();
const ParamTable<TissueSpec>& tissueTable();
const ParamTable<LayerSpec>& layerTable();
const ParamTable<materials::MaterialSpec>& materialTable();
const ParamTable<materials::PronyTerm>& pronyTable();
const ParamTable<InclusionSpec>& inclusionTable();
// tissue.geometry and its surfaces (read by tissue_geometry.cpp) and its placement: translate, rotate.
const ParamTable<ImportedGeometry>& geometryTable();
const ParamTable<ImportedGeometry>& surfaceTable();
struct Placement {
  double x = 0.0, y = 0.0, z = 0.0;  // m (translate) or rad (rotate)
};
const ParamTable<Placement>& offsetTable();
const ParamTable<Placement>& rotationTable();

const ParamTable<TissueSpec>& blockTable();
const ParamTable<NeedleSpec>& needleTable();
const ParamTable<InsertionSpec>& insertionTable();
// insertion.profile[i]: the segment (one key: its kind) and each kind's fields.
const ParamTable<MotionSegment>& segmentTable();
const ParamTable<MotionSegment>& segmentKindTable(const std::string& kind);  // insert, pause, retract, rotate
// model.engine and model.time_step; each engine's section model.<engine> is its own (model_section.hpp).
const ParamTable<ModelSpec>& modelTable();
const ParamTable<OutputSpec>& outputTable();
// output.units: one row per display dimension (units::displayDimensions).
const ParamTable<units::DisplayUnits>& unitsTable();
const ParamTable<FrictionSpec>& frictionTable();
const ParamTable<LayerSpec>& punctureTable();
const ParamTable<LayerSpec>& cuttingTable();
const ParamTable<LayerSpec>& interactionTable();

}  // namespace needlesim::scenario
