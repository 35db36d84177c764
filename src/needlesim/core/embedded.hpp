#pragma once
// Texts compiled into the binary by cmake/Embed.cmake.
#include <string_view>

namespace needlesim::embedded {
extern const std::string_view kChartJs;          // Chart.js (MIT), Debian libjs-chart.js
extern const std::string_view kDefaultScenario;  // examples/gelatin_18G_3mms.yaml
extern const std::string_view kReferences;       // docs/references.md
}  // namespace needlesim::embedded
