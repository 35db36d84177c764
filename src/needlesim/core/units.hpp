#pragma once
// Physical quantities with units. Scenario files write "6 mm/s", "30.74 kPa",
// "20 deg"; the code works in SI (m, kg, s, rad). A quantity whose unit is
// missing or of the wrong dimension is rejected with the unit that was expected.
#include <optional>
#include <string>
#include <string_view>

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

// Needle gauge (Stubs / ISO 9626 regular wall): outer and inner diameter in m.
struct GaugeSize {
  int gauge;
  double outer;
  double inner;
};
std::optional<GaugeSize> gaugeSize(int gauge);

}  // namespace needlesim::units
