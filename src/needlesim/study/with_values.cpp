#include "needlesim/study/with_values.hpp"

#include "needlesim/study/field_path.hpp"
#include "needlesim/study/study.hpp"

namespace needlesim::study {

std::string withValuesYaml(const std::string& baseYaml, const std::vector<std::pair<std::string, std::string>>& values,
                           const SourceLocation& where, const std::string& field) {
  Case c;
  for (const auto& [path, value] : values) {
    try {
      checkFieldPath(baseYaml, path);
    } catch (const FieldPathError& e) {
      throw fieldPathInputError(e, where, field, path);
    }
    c.assignments.emplace_back(path, value);
  }
  return caseYaml(baseYaml, c);
}

}  // namespace needlesim::study
