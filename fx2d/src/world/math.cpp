// fx_atan2 from + - * / and sqrt only: IEEE 754 rounds those the same way on every platform, and
// libm's atan2f does not (glibc's x86-64 and aarch64 builds differ in the last place for some
// inputs), so an angle read back from a rotation is the same to the bit everywhere.
#include <cmath>
#include <limits>

#include "fx2d/Math.h"

namespace fx2d {
namespace {

constexpr double pi = 3.14159265358979323846;
constexpr double tan_pi_8 = 0.41421356237309504880;

// atan(u) for |u| <= tan(pi/8): one half-angle step, atan(u) = 2 atan(u / (1 + sqrt(1 + u^2))),
// brings |u| under 0.2, where 13 terms of the Taylor series leave an error below 1e-18.
double atan_small(double u) {
  const double v = u / (1.0 + std::sqrt(1.0 + u * u));
  const double v2 = v * v;
  double sum = 0.0;
  for (int k = 12; k >= 0; --k) sum = sum * v2 + (k % 2 == 0 ? 1.0 : -1.0) / (2 * k + 1);
  return 2.0 * v * sum;
}

// atan(t) for t in [0, 1]: above tan(pi/8), atan(t) = pi/4 + atan((t - 1) / (t + 1)).
double atan_unit(double t) { return t > tan_pi_8 ? pi / 4 + atan_small((t - 1.0) / (t + 1.0)) : atan_small(t); }

}  // namespace

float fx_atan2(float y, float x) {
  if (std::isnan(x) || std::isnan(y)) return std::numeric_limits<float>::quiet_NaN();
  const double ax = std::fabs(static_cast<double>(x));
  const double ay = std::fabs(static_cast<double>(y));
  const bool steep = ay > ax;
  // The smaller over the larger, in [0, 1]; 0/0 and inf/inf have the limits std::atan2 gives.
  double t = steep ? ax / ay : ay / ax;
  if (ax == 0.0 && ay == 0.0) t = 0.0;
  if (std::isinf(ax) && std::isinf(ay)) t = 1.0;
  double angle = atan_unit(t);
  if (steep) angle = pi / 2 - angle;
  if (std::signbit(x)) angle = pi - angle;
  return static_cast<float>(std::copysign(angle, static_cast<double>(y)));
}

}  // namespace fx2d
