// The crack path of model.explicit.cohesive, read and checked (cohesive_path_section.hpp).
#include "needlesim/engines/explicit/cohesive_path_section.hpp"

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <functional>

#include "needlesim/io/csv_reader.hpp"

namespace needlesim::scenario {

namespace {
using Err = std::function<InputError(const std::string& field, const std::string& value, const std::string& problem,
                                     const std::string& allowed)>;
using Point = ExplicitCohesiveSpec::PathPoint;

// Point i of the path after `prev` (the points so far); err names where it came from.
void checkPoint(const Scenario& sc, const std::vector<Point>& prev, const Point& p, const Err& err) {
  const double ylo = -0.5 * sc.tissue.width - sc.insertion.entry_offset, yhi = ylo + sc.tissue.width;
  if (prev.empty() && (p.x != 0.0 || p.y != 0.0))
    throw err("x", fmt::format("({:g}, {:g}) mm", p.x * 1e3, p.y * 1e3), "does not start at the entry point",
              "the first point x: 0 mm, y: 0 mm");
  if (p.x > sc.tissue.length || !(p.y > ylo && p.y < yhi))
    throw err("x", fmt::format("({:g}, {:g}) mm", p.x * 1e3, p.y * 1e3), "lies outside the tissue block",
              fmt::format("0 <= x <= {:g} mm, {:g} mm < y < {:g} mm", sc.tissue.length * 1e3, ylo * 1e3, yhi * 1e3));
  if (prev.empty()) return;
  const Point& q = prev.back();
  if (!(p.x > q.x))
    throw err("x", fmt::format("{:g} mm", p.x * 1e3),
              "does not increase along the path (the path must be monotone along the insertion direction)",
              fmt::format("> {:g} mm", q.x * 1e3));
  if (std::abs(p.y - q.y) > p.x - q.x)
    throw err("y", fmt::format("{:g} mm", p.y * 1e3),
              "turns the path more than 45 deg away from the insertion axis (the seam morph would fold elements)",
              fmt::format("{:g} mm <= y <= {:g} mm", (q.y - (p.x - q.x)) * 1e3, (q.y + (p.x - q.x)) * 1e3));
}
}  // namespace

void readCohesivePath(Section& cs, const ExplicitModelSpec& x, ExplicitCohesiveSpec& c, const Scenario& sc) {
  const std::string& source = sc.source;
  c.path = cs.choice("path");
  c.path_radius = cs.number("path_radius");
  auto pts = cs.list("path_points");
  for (std::size_t i = 0; i < pts.size(); ++i) {
    Section e = cs.element(pts[i], "path_points", i);
    const Point p{e.number("x"), e.number("y")};
    checkPoint(sc, c.path_points, p, [&](auto&&... a) { return e.error(a...); });
    c.path_points.push_back(p);
  }
  // path_file: the points from a CSV ('x [mm]', 'y [mm]', any length unit), relative to the scenario file
  const std::string file = cs.text("path_file");
  if (!file.empty()) {
    if (!c.path_points.empty())
      throw cs.error("path_file", file, "is given together with path_points", "one of path_points, path_file");
    std::filesystem::path p(file);
    if (p.is_relative() && !source.empty() && source[0] != '<') p = std::filesystem::path(source).parent_path() / p;
    if (!std::filesystem::exists(p))
      throw cs.error("path_file", file, "does not exist (paths are relative to the scenario file)",
                     "a CSV file with columns 'x [mm]' and 'y [mm]'");
    const io::CsvData d = io::readCsv(p);
    const int cx = d.require({"x"}, units::Dim{1, 0, 0, 0}, "the depth of each path point from the entry face");
    const int cy = d.require({"y"}, units::Dim{1, 0, 0, 0}, "the lateral offset of each path point");
    for (std::size_t r = 0; r < d.rows(); ++r) {
      const Point q{d.col(cx)[r], d.col(cy)[r]};
      checkPoint(sc, c.path_points, q, [&](const std::string& f, const std::string& v, const std::string& pr,
                                           const std::string& al) {
        return InputError(SourceLocation{p.string(), d.lines[r], 0}, f, v, pr, al);
      });
      c.path_points.push_back(q);
    }
  }
  if (c.path != "straight") {
    const bool aligned = std::abs(sc.insertion.entry_angle - 0.5 * M_PI) < 1e-9 &&
                         std::abs(std::sin(sc.insertion.bevel_orientation)) < 1e-9;
    std::string why;
    if (!c.enable) why = "needs the cohesive zone (enable: true)";
    else if (x.dimension == 3) why = "is 2d only";
    else if (!aligned) why = "needs entry_angle 90 deg and bevel_orientation 0 or 180 deg";
    else if (x.needle_model != "rigid") why = "needs needle_model: rigid (the needle follows the path)";
    else if (c.path == "points" && c.path_points.size() < 2) why = "needs at least 2 path_points (or a path_file)";
    else if (c.path == "arc" && !(std::abs(c.path_radius) > 4 * sc.needle.outer_diameter))
      why = fmt::format("needs |path_radius| > 4 needle diameters ({:g} mm)", 4e3 * sc.needle.outer_diameter);
    for (const auto& m : sc.insertion.segments)
      if (why.empty() && m.kind == MotionSegment::Kind::Rotate) why = "keeps the bevel fixed: no rotate segments";
    if (!why.empty()) throw cs.error("path", c.path, why, "path: straight, or a 2d cohesive run that meets this");
  }
  if (!c.path_points.empty() && c.path != "points")
    throw cs.error(file.empty() ? "path_points" : "path_file", fmt::format("{} points", c.path_points.size()),
                   "are given but path is " + c.path, "path: points, or no path points");
}

}  // namespace needlesim::scenario
