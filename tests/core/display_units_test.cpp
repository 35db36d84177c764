// Display units (core/units): the shared conversion of a result in SI to the unit the
// scenario shows it in, and of a plot axis (results/display_units).
#include <gtest/gtest.h>

#include <cmath>

#include "needlesim/core/units.hpp"
#include "needlesim/results/display_units.hpp"

namespace u = needlesim::units;

TEST(DisplayUnits, ConvertsSiToTheChosenUnitOfItsDimension) {
  u::DisplayUnits d;
  d.set("length", "mm");
  d.set("force", "mN");
  d.set("stress", "kPa");
  EXPECT_EQ(u::shown(0.0025, "m", d).unit, "mm");
  EXPECT_DOUBLE_EQ(u::shown(0.0025, "m", d).value, 2.5);
  EXPECT_DOUBLE_EQ(u::shown(0.3, "N", d).value, 300.0);
  EXPECT_DOUBLE_EQ(u::shown(30740.0, "Pa", d).value, 30.74);
  EXPECT_EQ(u::shown(30740.0, "Pa", d).unit, "kPa");
}

TEST(DisplayUnits, CompoundAndUnchosenUnitsStayAsTheyAre) {
  u::DisplayUnits d;
  d.set("length", "mm");
  for (const char* unit : {"N/m", "J/m^2", "1/m", "N/m^2", "N m^2", "1"}) {
    EXPECT_EQ(u::shown(4.0, unit, d).unit, unit);
    EXPECT_EQ(u::shown(4.0, unit, d).value, 4.0);
  }
  EXPECT_EQ(u::shown(2.0, "s", d).unit, "s");  // time not chosen: SI
  EXPECT_EQ(u::shown(0.5, "N", d).unit, "N");
}

TEST(DisplayUnits, AnglesMomentsAndAxesInOtherUnits) {
  u::DisplayUnits d;
  d.set("angle", "deg");
  d.set("moment", "N mm");
  d.set("length", "um");
  EXPECT_NEAR(u::shown(0.5 * 3.141592653589793, "rad", d).value, 90.0, 1e-12);
  EXPECT_NEAR(u::shown(2e-3, "N m", d).value, 2.0, 1e-12);
  // an axis drawn in mm shown in um
  EXPECT_NEAR(u::shown(2.5, "mm", d).value, 2500.0, 1e-9);
  // no length chosen: SI, rescaled to the unit that reads 2.5
  EXPECT_NEAR(u::shown(2.5, "mm", u::DisplayUnits{}).value, 2.5, 1e-12);
  EXPECT_EQ(u::shown(2.5, "mm", u::DisplayUnits{}).unit, "mm");
  EXPECT_EQ(u::shown(0.5, "m", u::DisplayUnits{}).unit, "m");
}

TEST(DisplayUnits, APreferredUnitIsRescaledWhenItsValuesLeaveTheReadableRange) {
  u::DisplayUnits d;
  d.prefer("time", "ms");
  d.prefer("length", "mm");
  EXPECT_EQ(u::shown(2.85, "s", d).unit, "s");  // not "2.85e+03 ms"
  EXPECT_NEAR(u::shown(2.85, "s", d).value, 2.85, 1e-12);
  EXPECT_EQ(u::shown(0.004, "s", d).unit, "ms");  // in range: the preferred unit
  EXPECT_EQ(u::shown(1500.0, "s", d).unit, "min");
  EXPECT_EQ(u::shown(3.0, "m", d).unit, "m");
  EXPECT_EQ(u::shown(2e-6, "m", d).unit, "um");
  EXPECT_EQ(d.unitFor("s", 20.0), "s");  // an axis up to 20 s
  u::DisplayUnits fixed;
  fixed.set("time", "ms");  // output.units: kept whatever the values
  EXPECT_EQ(u::shown(2.85, "s", fixed).unit, "ms");
  EXPECT_NEAR(u::shown(2.85, "s", fixed).value, 2850.0, 1e-9);
  u::DisplayUnits angles;
  angles.prefer("angle", "deg");
  EXPECT_EQ(u::shown(1e-4, "rad", angles).unit, "deg");  // angles are never rescaled
}

TEST(DisplayUnits, RoundOffIsShownAsZeroWithoutSign) {
  u::DisplayUnits d;
  d.prefer("length", "mm");
  const u::Shown tiny = u::shown(-5.2e-18, "m", d);
  EXPECT_EQ(tiny.unit, "mm");
  EXPECT_EQ(tiny.value, 0.0);
  EXPECT_FALSE(std::signbit(tiny.value));
  EXPECT_EQ(needlesim::results::shownText(-0.0, "N", d), "0 N");
  EXPECT_EQ(needlesim::results::shownText(-5.2e-18, "m", d), "0 mm");
  EXPECT_EQ(needlesim::results::shownText(2e-9, "m", d), "2 nm");  // small but not round-off
  // in a column up to 0.05 m, 1e-12 m is round-off
  EXPECT_EQ(needlesim::results::shownText(1e-12, "m", d, "{:.6g}", 0.05), "0 mm");
}

TEST(DisplayUnits, PlotAxesMarkersAndLabelsAreConverted) {
  u::DisplayUnits d;
  d.set("length", "cm");
  d.set("force", "mN");
  needlesim::io::Plot p{"F", "tip depth [mm]", "force [N]", {{"total", {10.0, 20.0}, {0.1, 0.2}, false, false}}};
  p.xmarkers.push_back({15.0, "skin | fat"});
  const auto q = needlesim::results::inDisplayUnits(p, d);
  EXPECT_EQ(q.xlabel, "tip depth [cm]");
  EXPECT_EQ(q.ylabel, "force [mN]");
  EXPECT_NEAR(q.series[0].x[1], 2.0, 1e-12);
  EXPECT_NEAR(q.series[0].y[0], 100.0, 1e-12);
  EXPECT_NEAR(q.xmarkers[0].x, 1.5, 1e-12);
  needlesim::io::Plot e{"E", "time [s]", "KE / IE [-]", {{"r", {1.0}, {0.5}, false, false}}};
  const auto f = needlesim::results::inDisplayUnits(e, d);
  EXPECT_EQ(f.ylabel, "KE / IE [-]");
  EXPECT_EQ(f.series[0].y[0], 0.5);
}

TEST(DisplayUnits, ShownTextHasTheUnitAndNoUnitForPlainNumbers) {
  u::DisplayUnits d;
  d.set("length", "mm");
  EXPECT_EQ(needlesim::results::shownText(0.25, "m", d), "250 mm");
  EXPECT_EQ(needlesim::results::shownText(4.0, "1/m", d), "4 1/m");
  EXPECT_EQ(needlesim::results::shownText(0.5, "1", d), "0.5");
  EXPECT_EQ(needlesim::results::shownText(NAN, "m", d), "n/a");
  EXPECT_EQ(needlesim::results::shownText(-INFINITY, "m", d), "none");  // no crack tip yet
}

TEST(DisplayUnits, APlotAxisIsShownInTheUnitThatReadsItsLargestValue) {
  u::DisplayUnits d;
  d.prefer("time", "ms");
  d.prefer("force", "N");
  needlesim::io::Plot p{"F", "time [s]", "force [N]", {{"f", {0.0, 10.0, 20.0}, {-1e-17, 0.5, 1.0}, false, false}}};
  p.xmarkers.push_back({10.0, "pause"});
  const auto q = needlesim::results::inDisplayUnits(p, d);
  EXPECT_EQ(q.xlabel, "time [s]");  // 20 s, not 20000 ms
  EXPECT_EQ(q.series[0].x[2], 20.0);
  EXPECT_EQ(q.xmarkers[0].x, 10.0);
  EXPECT_EQ(q.ylabel, "force [N]");
  EXPECT_EQ(q.series[0].y[0], 0.0);
  EXPECT_FALSE(std::signbit(q.series[0].y[0]));
}
