// Example 3: fit a hyperelastic law to compression data.
//
// examples/data/plastisol_compression.csv holds a uniaxial compression test of a soft
// plastisol phantom (strain [%], stress [kPa]). `law = "auto"` fits every hyperelastic
// law and keeps the best (docs/fitting.md); the parameters come back in SI.
//
// Usage: ex3_fit EXAMPLES_FOLDER
#include <cstdio>
#include <filesystem>

#include <needlesim/needlesim.hpp>

namespace api = needlesim::api;

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s EXAMPLES_FOLDER\n", argv[0]);
    return 2;
  }
  try {
    api::FitOptions options;
    options.data = {std::filesystem::path(argv[1]) / "data/plastisol_compression.csv"};
    options.law = "auto";
    options.write = false;  // compute only; true writes fit.json and report.html
    const api::FitResults fitted = api::fit(options);

    std::printf("fitted law: %s\n", fitted.law.c_str());
    for (const auto& p : fitted.parameters)
      std::printf("  %-6s = %.6g %s (std. error %.3g)\n", p.name.c_str(), p.value, p.unit.c_str(), p.stdError);
    std::printf("for a scenario file:\n  %s\n", fitted.materialYaml.c_str());
    return 0;
  } catch (const api::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
}
