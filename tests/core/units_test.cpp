#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "needlesim/core/units.hpp"

using namespace needlesim::units;

TEST(Units, ParsesSpeedPressureAngleToSI) {
  EXPECT_DOUBLE_EQ(parse("6 mm/s").value, 6e-3);
  EXPECT_EQ(parse("6 mm/s").dim, dim::Velocity);
  EXPECT_DOUBLE_EQ(parse("30.74 kPa").value, 30740.0);
  EXPECT_EQ(parse("30.74 kPa").dim, dim::Pressure);
  EXPECT_NEAR(parse("20 deg").value, 20.0 * std::numbers::pi / 180.0, 1e-15);
  EXPECT_EQ(parse("20 deg").dim, dim::Angle);
  EXPECT_DOUBLE_EQ(parse("200 GPa").value, 200e9);
}

TEST(Units, CompoundUnits) {
  auto q = parse("285.053 N s/m^2");
  EXPECT_DOUBLE_EQ(q.value, 285.053);
  EXPECT_EQ(q.dim, dim::ForceTimePerArea);
  EXPECT_NEAR(parse("1 g/cm^3").value, 1000.0, 1e-9);
  EXPECT_EQ(parse("1 g/cm^3").dim, dim::Density);
  EXPECT_EQ(parse("3.791 N/m").dim, dim::ForcePerLength);
  EXPECT_EQ(parse("39.3 kJ/m^2").dim, dim::ForcePerLength);
  EXPECT_DOUBLE_EQ(parse("39.3 kJ/m^2").value, 39300.0);
  EXPECT_EQ(parse("2 1/s").dim, dim::Frequency);
  EXPECT_NEAR(parse("60 rpm").value, 2.0 * std::numbers::pi, 1e-12);
  EXPECT_DOUBLE_EQ(parse("1 N*m").value, 1.0);
  EXPECT_EQ(parse("1 N*m").dim, dim::Moment);
}

TEST(Units, PlainNumberIsDimensionlessAndGaugeIsFlagged) {
  EXPECT_EQ(parse("0.422").dim, dim::None);
  EXPECT_DOUBLE_EQ(parse("1e-3").value, 1e-3);
  auto g = parse("18 G");
  EXPECT_TRUE(g.gauge);
  EXPECT_DOUBLE_EQ(g.value, 18.0);
  EXPECT_DOUBLE_EQ(parse("50 %").value, 0.5);
}

TEST(Units, RejectsGarbage) {
  EXPECT_THROW(parse(""), std::invalid_argument);
  EXPECT_THROW(parse("kPa"), std::invalid_argument);
  EXPECT_THROW(parse("3 furlongs"), std::invalid_argument);
  EXPECT_THROW(parse("3 m/s/s"), std::invalid_argument);
  EXPECT_THROW(parse("3 m^"), std::invalid_argument);
  EXPECT_THROW(parse("nan mm"), std::invalid_argument);
}

TEST(Units, GaugeTableMatchesIso9626For18G) {
  auto g = gaugeSize(18);
  ASSERT_TRUE(g);
  EXPECT_NEAR(g->outer, 1.270e-3, 1e-9);
  EXPECT_NEAR(g->inner, 0.838e-3, 1e-9);
  EXPECT_FALSE(gaugeSize(5));
}
