// Example 4: a parameter study.
//
// examples/studies/friction_speed_grid.yaml varies the insertion speed (4 values) and the
// dynamic friction C_p (3 values) of the lumped gelatin scenario: a grid of 12 cases, each
// run like `needlesim run`, gathered into study.csv, study.json and report.html.
//
// Usage: ex4_study EXAMPLES_FOLDER [STUDY_FOLDER]   (default: results/friction_speed_grid)
#include <cstdio>
#include <filesystem>

#include <needlesim/needlesim.hpp>

namespace api = needlesim::api;

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: %s EXAMPLES_FOLDER [STUDY_FOLDER]\n", argv[0]);
    return 2;
  }
  try {
    api::SweepOptions options;
    if (argc == 3) options.out = argv[2];
    options.resume = true;  // a second run reuses the cases already complete
    const api::SweepSummary study =
        api::sweep(std::filesystem::path(argv[1]) / "studies/friction_speed_grid.yaml", options);

    std::printf("study folder: %s\n", study.folder.string().c_str());
    std::printf("cases: %d (%d ran, %d reused, %zu failed)\n", study.cases, study.ran, study.reused,
                study.failed.size());
    for (int index : study.failed) std::printf("  case %d failed (see its folder)\n", index);
    std::printf("%s\n", study.failed.empty() ? "all cases complete: see study.csv and report.html"
                                              : "rerun to retry the failed cases");
    return study.failed.empty() ? 0 : 3;
  } catch (const api::InputError& e) {
    std::fprintf(stderr, "input error: %s\n", e.what());
    return 2;
  } catch (const api::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  }
}
