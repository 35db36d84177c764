#include "needlesim/scenario/measured_data.hpp"

#include <cctype>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::scenario {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

MeasuredCurve measuredCurveFrom(const io::CsvData& csv) {
  const int cd = csv.require({"depth", "displacement", "position", "insertion depth"}, units::dim::Length,
                             "the insertion depth");
  const int cf = csv.require({"force", "insertion force", "total force", "force_total"}, units::dim::Force,
                             "the measured force");
  MeasuredCurve c;
  c.path = csv.file;
  c.depth = csv.col(cd);
  c.force = csv.col(cf);
  return c;
}

MeasuredMarkers measuredMarkersFrom(const io::CsvData& csv, const std::vector<MpmMarkerSpec>& markers) {
  const int cd = csv.require({"depth", "displacement", "insertion depth"}, units::dim::Length, "the insertion depth");
  MeasuredMarkers out;
  out.path = csv.file;
  out.depth = csv.col(cd);
  std::string names;
  for (const MpmMarkerSpec& mk : markers) {
    const std::string n = lower(mk.name);
    if (!names.empty()) names.append(", ");
    names.append("'").append(n).append("_ux', '").append(n).append("_uy'");
    const int cx = csv.find({n + "_ux"}), cy = csv.find({n + "_uy"});
    if (cx < 0 && cy < 0) continue;
    if (cx < 0 || cy < 0)
      throw InputError({csv.file, csv.headerLine, 0}, "header", n + (cx < 0 ? "_uy" : "_ux"),
                       "marker '" + mk.name + "' needs both displacement columns",
                       "'" + n + "_ux [mm]' and '" + n + "_uy [mm]'");
    csv.checkDim(cx, units::dim::Length, "the x displacement of marker " + mk.name);
    csv.checkDim(cy, units::dim::Length, "the y displacement of marker " + mk.name);
    out.markers.push_back({mk.name, csv.col(cx), csv.col(cy)});
  }
  if (out.markers.empty())
    throw InputError({csv.file, csv.headerLine, 0}, "header", "", "no column of any simulated marker",
                     "column pairs " + (names.empty() ? std::string("(the scenario has no markers)") : names));
  return out;
}

void loadMeasuredData(MpmModelSpec& m) {
  // readCsv refuses an empty or malformed file (InputError naming file and line).
  if (!m.measured_force.path.empty()) m.measured_force = measuredCurveFrom(io::readCsv(m.measured_force.path));
  if (!m.measured_markers.path.empty())
    m.measured_markers = measuredMarkersFrom(io::readCsv(m.measured_markers.path), m.markers);
}

}  // namespace needlesim::scenario
