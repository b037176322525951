// Tests for Math.h: compensated addition, rotations and transforms.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "fx2d/Math.h"

namespace fx2d {
namespace {

// One float ulp of a value of order 1 is 1.2e-7; chains of a few roundings on values below 10
// stay within a few ulps of 10, so 1e-5 absolute (and 1e-6 on unit vectors) cannot hide an error
// of the wrong formula, which is of the order of the values themselves.
constexpr float coordinate_tolerance = 1.0e-5f;
constexpr float unit_tolerance = 1.0e-6f;

void expect_near(FxVec2f actual, FxVec2f expected, float tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
}

TEST(FxCarryAdd, KeepsSmallStepsFarFromOriginWhilePlainAdditionLosesThem) {
  // At 10000 a float ulp is 2^-10 ~ 9.8e-4, so a step of 1e-4 is below half an ulp: plain
  // addition rounds every step away and ends 100 short (1% of the sum). Compensated addition
  // loses only the rounding of the carry, about 1e-11 per step, 1e-5 over a million steps.
  constexpr int steps = 1'000'000;
  constexpr float step = 1.0e-4f;
  float plain = 10000.0f;
  float value = 10000.0f;
  float carry = 0.0f;
  for (int i = 0; i < steps; ++i) {
    plain += step;
    FxCarryAdd(value, carry, step);
  }
  const double exact = 10000.0 + steps * double(step);
  EXPECT_LT(std::abs(precise_value(value, carry) - exact) / exact, 1.0e-6);
  EXPECT_GT(std::abs(double(plain) - exact) / exact, 1.0e-3);
}

TEST(FxCarryAdd, VectorFormAccumulatesEachComponent) {
  FxVec2f value{-10000.0f, 10000.0f};
  FxVec2f carry;
  for (int i = 0; i < 100'000; ++i) FxCarryAdd(value, carry, {1.0e-4f, -1.0e-4f});
  EXPECT_NEAR(precise_value(value.x, carry.x), -10000.0 + 10.0, 1.0e-3);
  EXPECT_NEAR(precise_value(value.y, carry.y), 10000.0 - 10.0, 1.0e-3);
}

TEST(FxRot, RotateThenInverseRotateReturnsTheVector) {
  const FxRot q = FxRot::from_angle(2.3f);
  const FxVec2f v{3.0f, -4.0f};
  expect_near(inv_rotate(q, rotate(q, v)), v, coordinate_tolerance);
  EXPECT_NEAR(length(rotate(q, v)), 5.0f, coordinate_tolerance);
}

TEST(FxRot, QuarterTurnMapsXAxisToYAxis) {
  const FxRot q = FxRot::from_angle(0.5f * 3.14159265f);
  expect_near(rotate(q, {1.0f, 0.0f}), {0.0f, 1.0f}, unit_tolerance);
  expect_near(rotate(q, {0.0f, 1.0f}), {-1.0f, 0.0f}, unit_tolerance);
}

TEST(FxRot, ComposingRotationsAddsAnglesAndInvMulSubtractsThem) {
  const FxRot q = FxRot::from_angle(0.7f);
  const FxRot r = FxRot::from_angle(-1.9f);
  EXPECT_NEAR(mul(q, r).angle(), 0.7f - 1.9f, unit_tolerance);
  EXPECT_NEAR(inv_mul(q, r).angle(), -1.9f - 0.7f, unit_tolerance);
  const FxVec2f v{1.5f, 0.25f};
  expect_near(rotate(mul(q, r), v), rotate(q, rotate(r, v)), unit_tolerance);
}

TEST(FxRot, IntegrateRotationAdvancesByAtanOfDeltaAndStaysUnit) {
  const FxRot start = FxRot::from_angle(0.3f);
  for (const float delta : {1.0e-3f, 1.0e-2f, 0.1f, -0.05f}) {
    const FxRot end = integrate_rotation(start, delta);
    const float advanced = inv_mul(start, end).angle();
    // The angle advanced is atan(delta) up to a few float roundings (1e-6 covers them); it falls
    // short of delta by at most |delta|^3 / 3.
    EXPECT_NEAR(advanced, std::atan(delta), unit_tolerance) << "delta " << delta;
    EXPECT_LE(std::abs(advanced - delta), std::abs(delta * delta * delta) / 3.0f + unit_tolerance)
        << "delta " << delta;
    EXPECT_NEAR(end.c * end.c + end.s * end.s, 1.0f, unit_tolerance);
  }
}

TEST(FxTransform, InverseTransformUndoesTransform) {
  const FxTransform xf{{4.0f, -2.5f}, FxRot::from_angle(1.1f)};
  const FxVec2f v{0.75f, 3.0f};
  expect_near(inv_transform_point(xf, transform_point(xf, v)), v, coordinate_tolerance);
}

TEST(FxTransform, InvMulExpressesBInAsFrame) {
  const FxTransform a{{1.0f, 2.0f}, FxRot::from_angle(0.4f)};
  const FxTransform b{{-3.0f, 0.5f}, FxRot::from_angle(-2.2f)};
  const FxTransform b_in_a = inv_mul(a, b);
  const FxVec2f v{0.6f, -1.2f};
  expect_near(transform_point(a, transform_point(b_in_a, v)), transform_point(b, v), coordinate_tolerance);
}

TEST(FxAABB, UnionEnclosesBothAndOverlapIncludesTouching) {
  const FxAABB a{{0.0f, 0.0f}, {1.0f, 1.0f}};
  const FxAABB b{{1.0f, 0.5f}, {2.0f, 3.0f}};
  const FxAABB u = union_of(a, b);
  EXPECT_TRUE(u.contains(a));
  EXPECT_TRUE(u.contains(b));
  EXPECT_FLOAT_EQ(u.perimeter(), 2.0f * (2.0f + 3.0f));
  EXPECT_TRUE(overlaps(a, b));
  EXPECT_FALSE(overlaps(a, FxAABB{{1.01f, 0.0f}, {2.0f, 1.0f}}));
}

// fx_atan2 is libm-free so that angles agree to the bit across platforms; it must still be
// atan2: within one float ulp of the double-precision answer, everywhere on the circle, and
// exactly rounded almost always.
TEST(FxAtan2, WithinOneUlpOfDoublePrecisionAtan2AroundTheCircle) {
  int exact = 0;
  const int samples = 100'000;
  for (int i = 0; i < samples; ++i) {
    // Angles over (-pi, pi] and radii over six decades, so every quadrant and octant and the
    // half-angle switch at tan(pi/8) are all crossed.
    const double angle = -3.14159265358979 + 6.28318530717958 * (i + 0.5) / samples;
    const double radius = std::pow(10.0, -3.0 + 6.0 * ((i * 7919) % samples) / samples);
    const float y = static_cast<float>(radius * std::sin(angle));
    const float x = static_cast<float>(radius * std::cos(angle));
    const float reference = static_cast<float>(std::atan2(static_cast<double>(y), static_cast<double>(x)));
    const float actual = fx_atan2(y, x);
    ASSERT_LE(std::fabs(actual - reference), std::nextafter(std::fabs(reference), 4.0f) - std::fabs(reference))
        << "atan2(" << y << ", " << x << ")";
    exact += actual == reference;
  }
  EXPECT_GE(exact, samples - samples / 1000);
}

TEST(FxAtan2, AxesZerosInfinitiesAndNanGiveWhatStdAtan2Gives) {
  const float inf = std::numeric_limits<float>::infinity();
  const float cases[][2] = {{0.0f, 1.0f},   {1.0f, 0.0f},   {0.0f, -1.0f}, {-1.0f, 0.0f}, {-0.0f, 1.0f},
                            {0.0f, -0.0f},  {-0.0f, -0.0f}, {0.0f, 0.0f},  {-0.0f, 0.0f}, {1.0f, 1.0f},
                            {-1.0f, -1.0f}, {inf, inf},     {-inf, inf},   {inf, -inf},   {1.0f, inf},
                            {1.0f, -inf},   {-1.0f, -inf},  {inf, 1.0f},   {3e-39f, 1.0f}, {1.0f, 3e-39f}};
  for (const auto& [y, x] : cases) {
    const float reference = static_cast<float>(std::atan2(static_cast<double>(y), static_cast<double>(x)));
    EXPECT_EQ(fx_atan2(y, x), reference) << "atan2(" << y << ", " << x << ")";
    EXPECT_EQ(std::signbit(fx_atan2(y, x)), std::signbit(reference)) << "atan2(" << y << ", " << x << ")";
  }
  EXPECT_TRUE(std::isnan(fx_atan2(std::nanf(""), 1.0f)));
  EXPECT_TRUE(std::isnan(fx_atan2(1.0f, std::nanf(""))));
}

}  // namespace
}  // namespace fx2d
