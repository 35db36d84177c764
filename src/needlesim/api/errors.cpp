// Public errors and the version.
#include "needlesim/api/translate.hpp"
#include "needlesim/core/version.hpp"

namespace needlesim::api {

InputError::InputError(const std::string& message, std::string file, int line, std::string field)
    : Error(message), file_(std::move(file)), line_(line), field_(std::move(field)) {}

std::string version() { return kVersion; }

namespace detail {

void argumentError(const std::string& call, const std::string& argument, const std::string& value,
                   const std::string& problem, const std::string& allowed) {
  const needlesim::InputError e(SourceLocation{"<C++ API>", 0, 0}, "needlesim::api::" + call + "(" + argument + ")",
                                value, problem, allowed);
  throw InputError(e.what(), e.where().file, e.where().line, e.field());
}

}  // namespace detail
}  // namespace needlesim::api
