#pragma once
// The settings of the lumped engine, model.lumped (seed 003 section 3.2).
// Plain structs in SI; the table in the .cpp declares each field once (key, unit, range,
// meaning; the default is the member's initial value) and reads it.
#include <string>
#include <vector>

namespace needlesim {
namespace scenario {
struct ModelSection;
}

struct LumpedModelSpec {
  double relaxation_time = 0.0;  // s, decay of the held friction during pauses (0 = none)
};

namespace engines {
// model.lumped: its schema rows and its reading (scenario/model_section.hpp).
const scenario::ModelSection& lumpedSection();
}  // namespace engines

}  // namespace needlesim
