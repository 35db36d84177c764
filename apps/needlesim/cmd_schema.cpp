// `needlesim schema`: every scenario field with its unit, default and range.
#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "commands.hpp"
#include "needlesim/scenario/schema.hpp"

namespace needlesim::app {

void registerSchemaCommand(CLI::App& app) {
  auto markdown = std::make_shared<bool>(false);
  auto* cmd = app.add_subcommand("schema", "List every scenario field with its unit, default and allowed range");
  cmd->add_flag("--markdown", *markdown, "print as the Markdown tables of docs/scenario-format.md");
  cmd->callback([markdown] {
    fmt::print("{}", *markdown ? scenario::schemaMarkdown() : scenario::schemaText());
  });
}

}  // namespace needlesim::app
