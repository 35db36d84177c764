#pragma once
// The block, needle, insertion, model (engine, time step), output and a layer's force sections
// (friction, puncture, cutting, interaction), each field declared once (scenario/parameter_table.hpp): the schema, the
// reader and the scenario as understood take these tables. Internal to the scenario reader.
#include "needlesim/scenario/parameter_table.hpp"
#include "needlesim/scenario/scenario.hpp"

namespace needlesim::scenario {

const ParamTable<TissueSpec>& blockTable();
const ParamTable<NeedleSpec>& needleTable();
const ParamTable<InsertionSpec>& insertionTable();
// insertion.profile[i]: the segment (one key: its kind) and each kind's fields.
const ParamTable<MotionSegment>& segmentTable();
const ParamTable<MotionSegment>& segmentKindTable(const std::string& kind);  // insert, pause, retract, rotate
// model.engine and model.time_step; each engine's section model.<engine> is its own (model_section.hpp).
const ParamTable<ModelSpec>& modelTable();
const ParamTable<OutputSpec>& outputTable();
const ParamTable<FrictionSpec>& frictionTable();
const ParamTable<LayerSpec>& punctureTable();
const ParamTable<LayerSpec>& cuttingTable();
const ParamTable<LayerSpec>& interactionTable();

}  // namespace needlesim::scenario
