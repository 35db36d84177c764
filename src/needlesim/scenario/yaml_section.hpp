#pragma once
// A YAML mapping being read against the schema: each getter consults the
// FieldDoc of (section type, key) for unit, default and range, and done()
// rejects keys that the schema does not know. Every value a getter returns
// (given or default) is also written into the Record, so the scenario as
// understood is one document in the input's own schema, quantities in SI with
// their unit (summary.json, docs/results.md). Internal to the reader.
#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "needlesim/core/error.hpp"
#include "needlesim/scenario/schema.hpp"

namespace needlesim::scenario {

// A unit of a display dimension and how often the file writes it: in the problem (tissue,
// needle, insertion) and in the solver's settings (model, output), which vote only for a
// dimension the problem does not write.
struct UnitWritten {
  std::string unit;
  int problem = 0;
  int settings = 0;
};

class Section {
 public:
  // The scenario as understood, and where each given field was written.
  struct Understood {
    nlohmann::json doc = nlohmann::json::object();
    std::map<std::string, SourceLocation> given_at;  // field path -> file:line:column
    // How often each unit of a display dimension (units::displayDimensions) was written,
    // in the order first written: the scenario's display units (output.units).
    std::vector<UnitWritten> units_written;
  };
  using Record = std::shared_ptr<Understood>;
  Section(YAML::Node node, std::string type, std::string path, std::shared_ptr<const std::string> file,
          Record record = nullptr);

  const std::string& type() const { return type_; }
  const std::string& path() const { return path_; }
  bool has(const std::string& key) const;

  // Quantity or plain number (for dimensionless fields), in SI.
  double number(const std::string& key);                // required, or the schema default
  std::optional<double> optNumber(const std::string& key);  // absent and no default -> nullopt
  // Outer diameter style: a length or a gauge ("18 G"); returns the quantity.
  units::Quantity lengthOrGauge(const std::string& key);
  std::string text(const std::string& key);            // String (default from schema text if any)
  std::string choice(const std::string& key);
  bool boolean(const std::string& key);
  Section sub(const std::string& key);                  // Section field (must be a mapping)
  std::vector<YAML::Node> list(const std::string& key);  // List field (must be a sequence)
  Section element(const YAML::Node& node, const std::string& key, std::size_t index);
  YAML::Node raw(const std::string& key) const;

  // A key the schema does not know is an error listing the allowed keys
  // (checked on construction, before any missing-field error).
  void checkKeys() const;

  InputError error(const std::string& key, const std::string& value, const std::string& problem,
                   const std::string& allowed) const;
  InputError errorAt(const YAML::Node& at, const std::string& field, const std::string& value,
                     const std::string& problem, const std::string& allowed) const;
  SourceLocation location(const YAML::Node& at) const;
  // Writes the value read for `key` into the record at this section's path
  // (for values the reader takes from raw(), such as a library material name),
  // and where the file gives it.
  void remember(const std::string& key, nlohmann::json value) const;
  std::string fieldPath(const std::string& key) const;
  // Records a number read or derived for `key` (a quantity with its SI unit).
  void rememberNumber(const std::string& key, double value) const;
  // The units of display dimensions written so far in the whole file, with their counts.
  std::vector<UnitWritten> unitsWritten() const;
  // Where the file gives each field read so far (the whole file's record).
  std::map<std::string, SourceLocation> givenAt() const;

 private:
  units::Quantity parseQuantity(const std::string& key, const FieldDoc& f, const YAML::Node& n,
                                const std::string& text);
  void rememberNumber(const std::string& key, const FieldDoc& f, double value) const;
  void countUnit(const units::Quantity& written) const;
  YAML::Node node_;
  std::string type_;
  std::string path_;
  std::shared_ptr<const std::string> file_;
  Record record_;
  mutable std::set<std::string> used_;
};

}  // namespace needlesim::scenario
