#pragma once
// A section model.<key> of a scenario, declared by the engine that reads it
// (engines/<engine>/<engine>_section.cpp) and registered with the engine (engines/registry.cpp):
// its schema rows and how it is read. The schema and the reader take every model section, and
// the engine names, from here; they name no engine.
#include <functional>
#include <string>
#include <vector>

#include "needlesim/scenario/schema.hpp"

namespace needlesim {
struct Scenario;
}

namespace needlesim::scenario {

class Section;

struct ModelSection {
  std::string key;   // model.<key>
  std::string help;  // its row in section `model`
  std::function<std::vector<FieldDoc>()> docs;  // its rows and those of the sections inside it
  // Reads model.<key> into the scenario (tissue, needle and insertion are read already) and
  // refuses what its engine cannot run (InputError at the field).
  std::function<void(Section&, Scenario&)> read;
};

// Every registered model section, each once, in the order of the engine registry.
const std::vector<const ModelSection*>& modelSections();
// The registered engines: name and one-line summary.
std::vector<std::pair<std::string, std::string>> engineNames();

}  // namespace needlesim::scenario
