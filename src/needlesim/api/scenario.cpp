// api::Scenario: read, validate and vary scenarios.
#include "needlesim/api/scenario_impl.hpp"
#include "needlesim/api/translate.hpp"
#include "needlesim/core/embedded.hpp"
#include "needlesim/scenario/reader.hpp"
#include "needlesim/scenario/yaml_document.hpp"
#include "needlesim/study/with_values.hpp"

namespace needlesim::api {

namespace {
Scenario fromText(std::string text, const std::string& source, std::filesystem::path folder = {}) {
  needlesim::Scenario typed = scenario::readText(text, source);
  return detail::ScenarioAccess::make(std::move(typed), std::move(text), std::move(folder));
}
}  // namespace

Scenario::Scenario(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}

Scenario Scenario::fromFile(const std::filesystem::path& path) {
  return detail::translated([&] {
    return fromText(scenario::readYamlFile(path, "a scenario file (see docs/scenario-format.md)"), path.string(),
                    study::dataFolderOf(path.string()));
  });
}

Scenario Scenario::fromYaml(const std::string& yaml, const std::string& source) {
  return detail::translated([&] { return fromText(yaml, source); });
}

Scenario Scenario::builtIn() {
  return detail::translated([] {
    return fromText(std::string(embedded::kDefaultScenario), "<built-in default: examples/gelatin_18G_3mms.yaml>");
  });
}

Scenario Scenario::with(const std::map<std::string, std::string>& values) const {
  return detail::translated([&] {
    const SourceLocation where{"<C++ API Scenario::with>", 0, 0};
    std::vector<std::pair<std::string, std::string>> assignments(values.begin(), values.end());
    // relative data paths (in the file or among the values) resolve from the scenario file's folder
    return fromText(study::withValuesYaml(impl_->yaml, assignments, where, "Scenario::with field path", impl_->folder),
                    where.file, impl_->folder);
  });
}

Scenario Scenario::with(const std::string& fieldPath, const std::string& value) const {
  return with(std::map<std::string, std::string>{{fieldPath, value}});
}

std::string Scenario::name() const { return impl_->scenario.name; }
std::string Scenario::engine() const { return impl_->scenario.model.engine; }
double Scenario::duration() const { return impl_->scenario.totalDuration(); }
const std::string& Scenario::yaml() const { return impl_->yaml; }

}  // namespace needlesim::api
