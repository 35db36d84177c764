#include "needlesim/scenario/scenario.hpp"

#include <algorithm>
#include <cmath>

namespace needlesim {

std::size_t TissueSpec::layerAt(double x) const {
  double end = 0.0;
  for (std::size_t i = 0; i + 1 < layers.size(); ++i)
    if (x <= (end += layers[i].thickness)) return i;
  return layers.empty() ? 0 : layers.size() - 1;
}

bool InclusionSpec::contains(double px, double py, double pz) const {
  if (shape == Shape::Mesh) return false;
  const double dx = px - x, dy = py - y, dz = shape == Shape::Cylinder ? 0.0 : pz - z;
  return dx * dx + dy * dy + dz * dz <= radius * radius;
}

double Scenario::maxDepth() const {
  double d = insertion.start_depth;
  for (const auto& s : insertion.segments)
    if (s.kind == MotionSegment::Kind::Insert) d = std::max(d, s.to_depth);
  return d;
}

double Scenario::totalDuration() const {
  double t = 0.0, depth = insertion.start_depth;
  for (const auto& s : insertion.segments) {
    switch (s.kind) {
      case MotionSegment::Kind::Insert:
      case MotionSegment::Kind::Retract:
        t += std::abs(s.to_depth - depth) / s.speed;
        depth = s.to_depth;
        break;
      case MotionSegment::Kind::Pause:
      case MotionSegment::Kind::Rotate: t += s.duration; break;
    }
  }
  return t;
}

}  // namespace needlesim

namespace needlesim {

SourceLocation Scenario::where(const std::string& field) const {
  for (std::string f = field; !f.empty();) {
    if (auto it = given_at.find(f); it != given_at.end()) return it->second;
    const SourceLocation* first = nullptr;  // the first given field inside section or list `f`
    for (auto it = given_at.lower_bound(f); it != given_at.end() && it->first.starts_with(f); ++it) {
      const char next = it->first.size() > f.size() ? it->first[f.size()] : '\0';
      const SourceLocation& at = it->second;
      if ((next == '.' || next == '[') &&
          (!first || at.line < first->line || (at.line == first->line && at.column < first->column)))
        first = &at;
    }
    if (first) return *first;
    const auto cut = f.find_last_of(".[");
    f = cut == std::string::npos ? std::string() : f.substr(0, cut);
  }
  return SourceLocation{source, 0, 0};
}

}  // namespace needlesim
