#pragma once
// Physical quantities with units. Scenario files write "6 mm/s", "30.74 kPa",
// "20 deg"; the code works in SI (m, kg, s, rad). A quantity whose unit is
// missing or of the wrong dimension is rejected with the unit that was expected.
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace needlesim::units {

// Exponents of length, mass, time and plane angle.
struct Dim {
  int L = 0, M = 0, T = 0, A = 0;
  friend bool operator==(const Dim&, const Dim&) = default;
};

namespace dim {
inline constexpr Dim None{};
inline constexpr Dim Length{1, 0, 0, 0};
inline constexpr Dim Mass{0, 1, 0, 0};
inline constexpr Dim Time{0, 0, 1, 0};
inline constexpr Dim Angle{0, 0, 0, 1};
inline constexpr Dim Velocity{1, 0, -1, 0};
inline constexpr Dim AngularVelocity{0, 0, -1, 1};
inline constexpr Dim Frequency{0, 0, -1, 0};
inline constexpr Dim Force{1, 1, -2, 0};
inline constexpr Dim Moment{2, 1, -2, 0};
inline constexpr Dim Pressure{-1, 1, -2, 0};
inline constexpr Dim Density{-3, 1, 0, 0};
inline constexpr Dim ForcePerLength{0, 1, -2, 0};        // N/m, also J/m^2 (toughness)
inline constexpr Dim ForceTimePerArea{-1, 1, -1, 0};     // N s/m^2 (friction damping per length)
inline constexpr Dim ForceTimePerLength{0, 1, -1, 0};    // N s/m (damping)
inline constexpr Dim TorqueTimePerAngle{2, 1, -1, -1};   // N m s/rad (rotational damping)
inline constexpr Dim StiffnessPerArea{-1, 1, -2, 0};     // N/m^2 (foundation stiffness per length)
inline constexpr Dim Energy{2, 1, -2, 0};
}  // namespace dim

struct Quantity {
  double value = 0.0;  // SI
  Dim dim;
  bool gauge = false;  // written in needle gauge ("18 G"); value is then the gauge number
  std::string unit;    // the unit as written ("mm", "%"); empty for a plain number
};

// Parses "<number> [unit]". Throws std::invalid_argument with a readable reason.
Quantity parse(std::string_view text);

// Canonical SI spelling of a dimension, e.g. "Pa", "m/s", "N s/m^2".
std::string siName(const Dim& d);
// A few units a user may write for this dimension, e.g. "Pa, kPa, MPa".
std::string examples(const Dim& d);
// An SI value written in the unit of `written` (a quantity as the user wrote it, e.g. "1 m" or
// "40 mm"): 0.06 and "1 mm" -> "60 mm". Plain SI with its unit when `written` has none.
std::string inUnitOf(double si, const Dim& d, std::string_view written);

// --- Display units: what a person reads (terminal, report) is shown in the scenario's units;
// files keep SI. A display dimension has a name (the key of `output.units`) and the units a
// scenario may choose for it; a result is converted only when its SI unit is exactly that
// dimension's SI name ("m", "N", "Pa"), so compound units (N/m, J/m^2, 1/m) stay as they are.
struct DisplayDimension {
  std::string_view name;  // "length", "force", "stress", ...
  Dim dim;
  std::string_view si;                 // SI name, e.g. "Pa"
  std::vector<std::string_view> units; // units allowed for display, SI first
  // The units a value may be rescaled to when the scenario does not fix the dimension's
  // unit (output.units), in the order tried; empty: never rescaled (angles).
  std::vector<std::string_view> rescaled = {};
};
const std::vector<DisplayDimension>& displayDimensions();
// The display dimension `name` ("length"), or nullptr.
const DisplayDimension* findDisplayDimension(std::string_view name);
// The display dimension whose display units include `unit` ("mm" -> length), or nullptr.
const DisplayDimension* displayDimensionOfUnit(std::string_view unit);

// The unit chosen per display dimension: fixed (output.units) or preferred (the unit the
// scenario writes most often, SI where none). A preferred unit is kept while the largest value
// shown in it lies in [0.1, 1000); otherwise the first of the dimension's `rescaled` units that
// shows it in [1, 1000) (else in [0.1, 1)) is used: 20 s, not 20000 ms.
class DisplayUnits {
 public:
  // Fixes the unit of `dimension` (a name of displayDimensions()); `unit` must be one of its units.
  void set(std::string_view dimension, std::string unit);
  // Prefers `unit` for `dimension`: used unless the values shown are out of [0.1, 1000).
  void prefer(std::string_view dimension, std::string unit);
  // The unit results of this SI unit are shown in: the chosen unit when `si_unit` is the SI
  // name of a display dimension with a chosen unit, else `si_unit` itself.
  std::string unitFor(std::string_view si_unit) const;
  // The unit values of `unit` whose largest magnitude is `largest` are shown in (rescaled
  // from the preferred unit as the class comment says; `largest` not finite or 0: unitFor).
  std::string unitFor(std::string_view unit, double largest) const;
  // Whether output.units fixed the unit of this display dimension.
  bool fixed(std::string_view dimension) const;
  // (dimension name, unit) pairs in the order of displayDimensions().
  std::vector<std::pair<std::string, std::string>> chosen() const;
  bool empty() const { return units_.empty(); }

 private:
  std::vector<std::pair<std::string, std::string>> units_;
  std::vector<std::string> fixed_;  // dimensions set() by output.units
};

// A value in a unit the display may show.
struct Shown {
  double value;
  std::string unit;
};
// `value` given in `unit` (SI for results and columns, or any unit of a display dimension,
// e.g. a plot axis in mm) in the display unit of its dimension: (0.0025, "m") with length
// in mm -> (2.5, "mm"). Unchanged when the unit is not one of a display dimension.
// The unit is DisplayUnits::unitFor(unit, largest), `largest` being |value| unless given
// (the largest magnitude of an axis or column the value is shown with). Round-off is shown
// as 0: a value below 1e-9 of `largest`, or a single value below 1e-9 of its preferred unit;
// never -0.
Shown shown(double value, std::string_view unit, const DisplayUnits& display, double largest = -1.0);
// The factor converting a value in `from` to `to`, both units of the same dimension.
double conversionFactor(std::string_view from, std::string_view to);

// Needle gauge (Stubs / ISO 9626 regular wall): outer and inner diameter in m.
struct GaugeSize {
  int gauge;
  double outer;
  double inner;
};
std::optional<GaugeSize> gaugeSize(int gauge);

}  // namespace needlesim::units
