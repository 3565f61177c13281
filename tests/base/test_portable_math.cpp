// portable_math: the functions whose results decide rays, trees and records
// must give the same bits everywhere (pinned here), stay close to the true
// values (so images do not shift), and the build must not fuse a*b+c.
#include "nodetrace/base/portable_math.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace {

namespace math = nodetrace::base::portable_math;

// Distance in units in the last place of `reference` (rounded to double).
double ulp_error(double value, long double reference) {
  const double rounded = static_cast<double>(reference);
  const double ulp = std::nextafter(std::fabs(rounded), std::numeric_limits<double>::infinity()) - std::fabs(rounded);
  return static_cast<double>(std::fabs(static_cast<long double>(value) - reference) / ulp);
}

float camera_half_angle(int hundredths_of_a_degree) {
  // The expression the camera evaluates (tracer/src/render/camera.cpp).
  const float fov = static_cast<float>(hundredths_of_a_degree) * 0.01f;
  return fov * 0.5f * 3.14159265f / 180.0f;
}

std::int32_t float_ulps_apart(float a, float b) {
  std::int32_t x, y;
  std::memcpy(&x, &a, sizeof x);
  std::memcpy(&y, &b, sizeof y);
  return x > y ? x - y : y - x;  // both positive here
}

TEST(PortableMath, CameraAnglesAreCorrectlyRoundedAndWithinOneUlpOfTheCLibrary) {
  // Every field of view the tracer accepts in steps of 0.01 degree, 22.96,
  // 13.18 and 26.30 among them (where glibc's tanf differs between machines).
  for (int hundredths = 1; hundredths < 18000; ++hundredths) {
    const float angle = camera_half_angle(hundredths);
    SCOPED_TRACE("fov " + std::to_string(hundredths / 100.0));
    EXPECT_EQ(math::tan(angle), static_cast<float>(tanl(angle)));
    EXPECT_EQ(math::sin(angle), static_cast<float>(sinl(angle)));
    EXPECT_LE(float_ulps_apart(math::tan(angle), std::tan(angle)), 1);
    EXPECT_LE(float_ulps_apart(math::sin(angle), std::sin(angle)), 1);
  }
}

TEST(PortableMath, DoubleFunctionsAreCorrectlyRoundedAgainstLongDouble) {
  std::mt19937_64 random(31);
  std::uniform_real_distribution<double> angle(-10, 10), unit(-1, 1), exponent(-700, 700), positive(1e-300, 1e300);
  double worst_sin = 0, worst_cos = 0, worst_tan = 0, worst_atan2 = 0, worst_acos = 0, worst_exp = 0, worst_log2 = 0;
  for (int i = 0; i < 100000; ++i) {
    const double x = angle(random), u = unit(random), e = exponent(random), p = positive(random);
    worst_sin = std::max(worst_sin, ulp_error(math::sin(x), sinl(x)));
    worst_cos = std::max(worst_cos, ulp_error(math::cos(x), cosl(x)));
    worst_tan = std::max(worst_tan, ulp_error(math::tan(x), tanl(x)));
    worst_atan2 = std::max(worst_atan2, ulp_error(math::atan2(x, u), atan2l(x, u)));
    worst_acos = std::max(worst_acos, ulp_error(math::acos(u), acosl(u)));
    worst_exp = std::max(worst_exp, ulp_error(math::exp(e), expl(e)));
    worst_log2 = std::max(worst_log2, ulp_error(math::log2(p), log2l(p)));
  }
  // Correctly rounded: half an ulp, and a little for long double's own error.
  const double bound = 0.5 + 1.0 / 1024;
  EXPECT_LE(worst_sin, bound);
  EXPECT_LE(worst_cos, bound);
  EXPECT_LE(worst_tan, bound);
  EXPECT_LE(worst_atan2, bound);
  EXPECT_LE(worst_acos, bound);
  EXPECT_LE(worst_exp, bound);
  EXPECT_LE(worst_log2, bound);
}

struct Pinned {
  const char* function;
  double argument;
  double result;
};

double evaluate(const std::string& function, double x) {
  if (function == "sin") return math::sin(x);
  if (function == "cos") return math::cos(x);
  if (function == "tan") return math::tan(x);
  if (function == "acos") return math::acos(x);
  if (function == "atan2") return math::atan2(x, -0.3);
  if (function == "exp") return math::exp(x);
  if (function == "log2") return math::log2(x);
  if (function == "sinf") return math::sin(static_cast<float>(x));
  if (function == "tanf") return math::tan(static_cast<float>(x));
  if (function == "powf") return math::pow(static_cast<float>(x), 37.0f);
  ADD_FAILURE() << "no function " << function;
  return 0;
}

TEST(PortableMath, ResultsArePinnedToTheBit) {
  // Computed once on x86-64; any change of algorithm, constant or evaluation
  // order (a fused multiply-add included) changes some of them.
  const Pinned pinned[] = {
    {"sin", 0x1.999999999999ap-4, 0x1.98eaecb8bcb2cp-4},
    {"cos", 0x1.999999999999ap-4, 0x1.fd712f9a817c1p-1},
    {"tan", 0x1.999999999999ap-4, 0x1.9af8877430b8p-4},
    {"sin", 0x1p-1, 0x1.eaee8744b05fp-2},
    {"cos", 0x1p-1, 0x1.c1528065b7d5p-1},
    {"tan", 0x1p-1, 0x1.17b4f5bf3474ap-1},
    {"sin", 0x1p+0, 0x1.aed548f090ceep-1},
    {"cos", 0x1p+0, 0x1.14a280fb5068cp-1},
    {"tan", 0x1p+0, 0x1.8eb245cbee3a6p+0},
    {"sin", 0x1.4p+1, 0x1.326af0dcfcab1p-1},
    {"cos", 0x1.4p+1, -0x1.9a2f7ef858b7dp-1},
    {"tan", 0x1.4p+1, -0x1.7e79b4e00bb15p-1},
    {"sin", -0x1.d99999999999ap+1, 0x1.0f46aec2e1b41p-1},
    {"cos", -0x1.d99999999999ap+1, -0x1.b23a2ad7dd937p-1},
    {"tan", -0x1.d99999999999ap+1, -0x1.3fdd037da3554p-1},
    {"sin", 0x1.4p+3, -0x1.1689ef5f34f52p-1},
    {"cos", 0x1.4p+3, -0x1.ad9ac890c6b1fp-1},
    {"tan", 0x1.4p+3, 0x1.4bf5f34be3782p-1},
    {"sin", 0x1.edd2f1a9fbe77p+6, -0x1.9b9dadc41aeb6p-1},
    {"cos", 0x1.edd2f1a9fbe77p+6, -0x1.307e5980a1558p-1},
    {"tan", 0x1.edd2f1a9fbe77p+6, 0x1.5a0fe5da94891p+0},
    {"sin", 0x1.e848p+19, -0x1.6664b255eced2p-2},
    {"cos", 0x1.e848p+19, 0x1.df9df9908b334p-1},
    {"tan", 0x1.e848p+19, -0x1.7e9768aaafecp-2},
    {"acos", 0x1p-2, 0x1.51700e0c14b25p+0},
    {"atan2", 0x1p-2, 0x1.393286347d276p+1},
    {"acos", -0x1.ccccccccccccdp-1, 0x1.586476251e745p+1},
    {"atan2", -0x1.ccccccccccccdp-1, -0x1.e47df3d0dd4dp+0},
    {"acos", 0x1.ff7ced916872bp-1, 0x1.6e634e566a29ep-5},
    {"atan2", 0x1.ff7ced916872bp-1, 0x1.dcceacaf4b1e5p+0},
    {"exp", -0x1.8p+1, 0x1.97db0ccceb0afp-5},
    {"exp", -0x1.47ae147ae147bp-7, 0x1.fae7cfd2b9cfep-1},
    {"exp", 0x1.6666666666666p-1, 0x1.01c2a61268987p+1},
    {"exp", 0x1.4p+4, 0x1.ceb088b68e804p+28},
    {"exp", -0x1.5ep+9, 0x1.14f2b0fb9307fp-1010},
    {"log2", 0x1.8p+1, 0x1.95c01a39fbd68p+0},
    {"log2", 0x1.4f8b588e368f1p-17, -0x1.09c1165ec0627p+4},
    {"log2", 0x1.117c4p+18, 0x1.21866e00ddab6p+4},
    {"log2", 0x1.78c29dccccccdp+23, 0x1.78eb88188858ep+4},
    {"sinf", 0x1.921fb6p-3, 0x1.8f8b84p-3},
    {"tanf", 0x1.921fb6p-3, 0x1.975f5ep-3},
    {"sinf", 0x1.921fb6p-2, 0x1.87de2cp-2},
    {"tanf", 0x1.921fb6p-2, 0x1.a8279ap-2},
    {"sinf", 0x1.4cccccp+0, 0x1.ed578p-1},
    {"tanf", 0x1.4cccccp+0, 0x1.cd11acp+1},
    {"powf", 0x1.dc28f5c28f5c3p-1, 0x1.1766dcp-4},
  };
  for (const Pinned& p : pinned) {
    EXPECT_EQ(evaluate(p.function, p.argument), p.result) << p.function << "(" << p.argument << ")";
  }
}

// The float sin and cos take a plain-double fast path where it cannot change
// the float: their bits must be those of the double functions rounded once,
// as before the fast path (traces keep their bytes), on the angles the path
// tracer draws (2 pi u), on every float of a few binades near the quadrant
// boundaries, and on large and tiny arguments.
TEST(PortableMath, FloatSinAndCosAreTheDoubleOnesRoundedToFloat) {
  const auto expect_same = [](float x) {
    const float s = math::sin(x), c = math::cos(x);
    const float es = static_cast<float>(math::sin(static_cast<double>(x)));
    const float ec = static_cast<float>(math::cos(static_cast<double>(x)));
    std::uint32_t a, b, d, e;
    std::memcpy(&a, &s, 4), std::memcpy(&b, &es, 4), std::memcpy(&d, &c, 4), std::memcpy(&e, &ec, 4);
    if (a != b || d != e) {
      ADD_FAILURE() << "x = " << x << " (" << std::hexfloat << x << "): sin " << s << " against " << es << ", cos "
                    << c << " against " << ec;
      return false;
    }
    return true;
  };
  std::mt19937 generator(49);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < 1000000; ++i) {
    if (!expect_same(6.28318530717958647692f * unit(generator))) return;
  }
  std::uniform_int_distribution<std::uint32_t> bits(0, 0xFFFFFFFFu);
  for (int i = 0; i < 300000; ++i) {
    const std::uint32_t b = bits(generator);
    float x;
    std::memcpy(&x, &b, 4);
    if (std::isfinite(x) && !expect_same(x)) return;
  }
  for (const float center : {0.78539816f, 1.5707963f, 3.1415927f, 4.712389f, 6.2831855f}) {
    float x = center;
    for (int i = 0; i < 20000; ++i, x = std::nextafter(x, 0.0f)) {
      if (!expect_same(x) || !expect_same(-x)) return;
    }
  }
  for (const float x : {0.0f, -0.0f, 1e-30f, -1e-30f, 1e-45f, 3e38f, -3e38f, 1e6f, 823550.f}) {
    if (!expect_same(x)) return;
  }
}

TEST(PortableMath, SpecialValuesFollowTheCLibrary) {
  const double inf = std::numeric_limits<double>::infinity(), nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(std::isnan(math::sin(inf)));
  EXPECT_TRUE(std::isnan(math::cos(nan)));
  EXPECT_TRUE(std::isnan(math::tan(-inf)));
  EXPECT_TRUE(std::isnan(math::acos(1.5)));
  EXPECT_TRUE(std::isnan(math::log2(-1)));
  EXPECT_EQ(math::sin(0.0), 0.0);
  EXPECT_EQ(math::cos(0.0), 1.0);
  EXPECT_EQ(math::acos(1.0), 0.0);
  EXPECT_EQ(math::acos(-1.0), std::acos(-1.0));
  EXPECT_EQ(math::atan2(0.0, -0.0), std::atan2(0.0, -0.0));
  EXPECT_EQ(math::atan2(-0.0, 1.0), 0.0);
  EXPECT_TRUE(std::signbit(math::atan2(-0.0, 1.0)));
  EXPECT_EQ(math::atan2(1.0, 0.0), std::atan2(1.0, 0.0));
  EXPECT_EQ(math::atan2(-inf, -inf), std::atan2(-inf, -inf));
  EXPECT_EQ(math::exp(0.0), 1.0);
  EXPECT_EQ(math::exp(710.0), inf);
  EXPECT_EQ(math::exp(-746.0), 0.0);
  EXPECT_EQ(math::log2(0.0), -inf);
  EXPECT_EQ(math::log2(inf), inf);
  for (int k = -1074; k <= 1023; ++k) ASSERT_EQ(math::log2(std::ldexp(1.0, k)), k) << "2^" << k;
  EXPECT_EQ(math::pow(0.0f, 0.0f), 1.0f);
  EXPECT_EQ(math::pow(0.0f, 3.0f), 0.0f);
  EXPECT_EQ(math::pow(0.0f, -1.0f), std::numeric_limits<float>::infinity());
  EXPECT_EQ(math::pow(2.0f, -1.0f), 0.5f);
  EXPECT_EQ(math::pow(-2.0f, 3.0f), -8.0f);
  EXPECT_TRUE(std::isnan(math::pow(-2.0f, 0.5f)));
  EXPECT_EQ(math::pow(1.0f, std::numeric_limits<float>::quiet_NaN()), 1.0f);
  // A hostile material's shininess: the lobe vanishes, nothing overflows.
  EXPECT_EQ(math::pow(0.999f, 1e30f), 0.0f);
  EXPECT_EQ(math::pow(std::numeric_limits<float>::infinity(), 2.0f), std::numeric_limits<float>::infinity());
}

TEST(FloatingPointBuild, DoesNotFuseMultiplyAndAdd) {
  // (1 + 2^-27)(1 - 2^-27) = 1 - 2^-54 rounds to 1, so a*b+c is 0; a fused
  // multiply-add keeps -2^-54. The project's flags (-ffp-contract=off) must
  // reach this file as they reach the tracer.
  volatile double a = 1 + 0x1p-27, b = 1 - 0x1p-27, c = -1;
  const double x = a, y = b, z = c;
  EXPECT_EQ(x * y + z, 0.0);
}

}  // namespace
