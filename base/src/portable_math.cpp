#include "nodetrace/base/portable_math.hpp"

#include <array>
#include <cmath>
#include <cstddef>
#include <limits>

namespace nodetrace::base::portable_math {
namespace {

// Double-double numbers: an unevaluated sum hi + lo with |lo| <= ulp(hi)/2,
// about 106 bits. Evaluated in double-double, a function's error stays near
// 2^-100 until the one rounding to double, so results are correctly rounded
// but where the true value lies that close to a midpoint: they then agree
// with any other correctly rounding library (glibc's sin and cos nearly are),
// and old traces keep their bytes. The error-free transformations below
// (Knuth's two-sum, Dekker's split and product) are exact only without
// contraction, which the build guarantees.
struct DD {
  double hi = 0, lo = 0;
};

constexpr DD quick_two_sum(double a, double b) {  // |a| >= |b|
  const double s = a + b;
  return {s, b - (s - a)};
}
constexpr DD two_sum(double a, double b) {
  const double s = a + b;
  const double v = s - a;
  return {s, (a - (s - v)) + (b - v)};
}
constexpr DD split(double a) {  // a = hi + lo, each with at most 26 significant bits
  const double t = 134217729.0 * a;  // 2^27 + 1
  const double hi = t - (t - a);
  return {hi, a - hi};
}
constexpr DD two_product(double a, double b) {
  const double p = a * b;
  const DD x = split(a), y = split(b);
  return {p, ((x.hi * y.hi - p) + x.hi * y.lo + x.lo * y.hi) + x.lo * y.lo};
}
constexpr DD operator+(DD a, DD b) {
  DD s = two_sum(a.hi, b.hi);
  const DD t = two_sum(a.lo, b.lo);
  s.lo += t.hi;
  s = quick_two_sum(s.hi, s.lo);
  s.lo += t.lo;
  return quick_two_sum(s.hi, s.lo);
}
constexpr DD operator-(DD a) { return {-a.hi, -a.lo}; }
constexpr DD operator-(DD a, DD b) { return a + -b; }
constexpr DD operator*(DD a, DD b) {
  DD p = two_product(a.hi, b.hi);
  p.lo += a.hi * b.lo + a.lo * b.hi;
  return quick_two_sum(p.hi, p.lo);
}
constexpr DD operator*(DD a, double b) {
  DD p = two_product(a.hi, b);
  p.lo += a.lo * b;
  return quick_two_sum(p.hi, p.lo);
}
constexpr DD operator/(DD a, DD b) {
  const double q1 = a.hi / b.hi;
  DD r = a - b * q1;
  const double q2 = r.hi / b.hi;
  r = r - b * q2;
  const double q3 = r.hi / b.hi;
  return quick_two_sum(q1, q2) + DD{q3, 0};
}
constexpr DD dd(double x) { return {x, 0}; }
double rounded(DD x) { return x.hi + x.lo; }

DD sqrt_dd(DD a) {
  if (a.hi <= 0) return {};
  const double s = std::sqrt(a.hi);
  const DD e = a - two_product(s, s);
  return quick_two_sum(s, e.hi / (2 * s));
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInfinity = std::numeric_limits<double>::infinity();

constexpr DD kPi{0x1.921fb54442d18p+1, 0x1.1a62633145c07p-53};
constexpr DD kHalfPi{0x1.921fb54442d18p+0, 0x1.1a62633145c07p-54};
constexpr DD kSixthPi{0x1.0c152382d7366p-1, -0x1.ee6913347c2a6p-55};
constexpr DD kSqrt3{0x1.bb67ae8584caap+0, 0x1.cec95d0b5c1e3p-54};
constexpr DD kInverseLn2{0x1.71547652b82fep+0, 0x1.777d0ffda0d24p-56};
constexpr double kQuarterPi = 0x1.921fb54442d18p-1;
constexpr double kTwoPi = 0x1.921fb54442d18p+2;
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
constexpr double kTanTwelfthPi = 0x1.126145e9ecd56p-2;  // 2 - sqrt(3)
constexpr double kSqrtHalf = 0x1.6a09e667f3bcdp-1;

// pi/2 in three parts, the first two with 33 significant bits, so k * part
// is exact for |k| < 2^20 and x - k pi/2 keeps about 120 bits.
constexpr double kHalfPi1 = 0x1.921fb544p+0;
constexpr double kHalfPi2 = 0x1.0b4611a6p-34;
constexpr double kHalfPi3 = 0x1.3198a2e037073p-69;
constexpr double kLargeArgument = 0x1p19 * 0x1.921fb54442d18p+0;

// ln 2 in three parts, the first with 32 significant bits: k * kLn2High is
// exact for every exponent k a double has.
constexpr double kLn2High = 0x1.62e42feep-1;
constexpr double kLn2Middle = 0x1.a39ef35793c76p-33;
constexpr double kLn2Low = 0x1.cc01f97b57a08p-87;
constexpr double kExpOverflow = 0x1.62e42fefa39efp+9;    // ln(DBL_MAX)
constexpr double kExpUnderflow = -0x1.74910d52d3052p+9;  // ln of half the least subnormal

// Taylor coefficients in double-double. Each series is cut where the first
// term left out is below 2^-70 of the sum on the kernel's interval.
enum class Signs { Same, Alternating };
template <std::size_t N>
constexpr std::array<DD, N> series(int first, int step, bool factorial, Signs signs) {
  std::array<DD, N> c{};
  DD reciprocal = dd(1);
  int n = 1;
  for (std::size_t i = 0; i < N; ++i) {
    const int order = first + step * static_cast<int>(i);
    if (factorial) {
      for (; n <= order; ++n) reciprocal = reciprocal / dd(n);
      c[i] = reciprocal;
    } else {
      c[i] = dd(1) / dd(order);
    }
    if (signs == Signs::Alternating && i % 2 == 1) c[i] = -c[i];
  }
  return c;
}

// sin r = r + r z S(z), S = -1/3! + z/5! - ... (to 1/23!), |r| <= pi/4.
constexpr auto kSin = [] {
  auto c = series<11>(3, 2, true, Signs::Alternating);
  for (DD& v : c) v = -v;
  return c;
}();
// cos r = C(z) = 1 - z/2! + z^2/4! - ... (to 1/24!).
constexpr auto kCos = series<13>(0, 2, true, Signs::Alternating);
// atan t = t + t z A(z), A = -1/3 + z/5 - ... (to 1/41), |t| <= 2 - sqrt(3).
constexpr auto kAtan = [] {
  auto c = series<20>(3, 2, false, Signs::Alternating);
  for (DD& v : c) v = -v;
  return c;
}();
// ln m = 2s (1 + z/3 + z^2/5 + ...) (to 1/31), s = (m-1)/(m+1), |s| <= 0.172.
constexpr auto kLog = series<16>(1, 2, false, Signs::Same);
// e^r = 1 + r + r^2/2! + ... (to 1/19!), |r| <= ln2 / 2.
constexpr auto kExp = series<20>(0, 1, true, Signs::Same);

template <std::size_t N>
DD horner(const std::array<DD, N>& c, DD z) {
  DD sum = c[N - 1];
  for (std::size_t i = N - 1; i-- > 0;) sum = sum * z + c[i];
  return sum;
}

DD sin_kernel(DD r) {
  const DD z = r * r;
  return r + r * z * horner(kSin, z);
}
DD cos_kernel(DD r) { return horner(kCos, r * r); }

struct Reduced {
  DD r;          // in [-pi/4, pi/4] up to rounding
  int quadrant;  // x = r + quadrant * pi/2 (mod 2 pi)
};

Reduced reduce_half_pi(double x) {
  if (std::fabs(x) <= kQuarterPi) return {dd(x), 0};
  if (std::fabs(x) > kLargeArgument) x = std::fmod(x, kTwoPi);
  const double k = std::round(x * kTwoOverPi);
  // x - k kHalfPi1 is exact (Sterbenz), and so are the products.
  const DD r = two_sum(x - k * kHalfPi1, -(k * kHalfPi2)) - two_product(k, kHalfPi3);
  return {r, static_cast<int>(static_cast<long long>(k) & 3)};
}

DD atan_kernel(DD t) {
  const DD z = t * t;
  return t + t * z * horner(kAtan, z);
}

// atan t for 0 <= t <= 1.
DD atan_unit(DD t) {
  if (t.hi <= kTanTwelfthPi) return atan_kernel(t);
  // atan t = pi/6 + atan((sqrt3 t - 1) / (sqrt3 + t)), the second argument
  // back under tan(pi/12).
  return kSixthPi + atan_kernel((kSqrt3 * t - dd(1)) / (kSqrt3 + t));
}

// The angle of (x, y) for y >= 0 as a double-double: atan2(y, x).
DD angle_of(DD y, double x) {
  double ax = std::fabs(x);
  if (std::isfinite(ax) && std::isfinite(y.hi) && (ax > 0x1p900 || y.hi > 0x1p900)) {
    ax *= 0x1p-200;  // Dekker's split overflows near DBL_MAX; the ratio is the same
    y = y * 0x1p-200;
  }
  DD angle;
  if (y.hi == 0 && ax == 0) {
    angle = {};
  } else if (std::isinf(y.hi) && std::isinf(ax)) {
    angle = {kQuarterPi, 0};
  } else if (std::isinf(y.hi)) {
    angle = kHalfPi;
  } else if (std::isinf(ax)) {
    angle = {};
  } else if (y.hi <= ax) {
    angle = atan_unit(y / dd(ax));
  } else {
    angle = kHalfPi - atan_unit(dd(ax) / y);
  }
  return std::signbit(x) ? kPi - angle : angle;
}

// ln m for m in [sqrt(1/2), sqrt(2)).
DD log_mantissa(double m) {
  const DD s = dd(m - 1.0) / two_sum(m, 1.0);
  return s * 2.0 * horner(kLog, s * s);
}

// x = m 2^e with m in [sqrt(1/2), sqrt(2)); x finite and > 0.
struct Split {
  double m;
  int e;
};
Split split_mantissa(double x) {
  int e = 0;
  double m = std::frexp(x, &e);
  if (m < kSqrtHalf) {
    m *= 2;
    --e;
  }
  return {m, e};
}

bool is_odd_integer(double y) {
  return std::fabs(y) < 0x1p53 && std::trunc(y) == y && std::fmod(y, 2.0) != 0;
}

}  // namespace

double sin(double x) {
  if (!std::isfinite(x)) return kNaN;
  const Reduced a = reduce_half_pi(x);
  switch (a.quadrant) {
    case 0: return rounded(sin_kernel(a.r));
    case 1: return rounded(cos_kernel(a.r));
    case 2: return -rounded(sin_kernel(a.r));
    default: return -rounded(cos_kernel(a.r));
  }
}

double cos(double x) {
  if (!std::isfinite(x)) return kNaN;
  const Reduced a = reduce_half_pi(x);
  switch (a.quadrant) {
    case 0: return rounded(cos_kernel(a.r));
    case 1: return -rounded(sin_kernel(a.r));
    case 2: return -rounded(cos_kernel(a.r));
    default: return rounded(sin_kernel(a.r));
  }
}

double tan(double x) {
  if (!std::isfinite(x)) return kNaN;
  const Reduced a = reduce_half_pi(x);
  const DD s = sin_kernel(a.r), c = cos_kernel(a.r);
  return (a.quadrant % 2 == 0) ? rounded(s / c) : -rounded(c / s);
}

double atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  return std::copysign(rounded(angle_of(dd(std::fabs(y)), x)), y);
}

double acos(double x) {
  if (!(std::fabs(x) <= 1)) return kNaN;
  // sin of the angle: sqrt(1 - x^2), with 1 - x^2 exact in double-double.
  return rounded(angle_of(sqrt_dd(dd(1) - two_product(x, x)), x));
}

double exp(double x) {
  if (std::isnan(x)) return x;
  if (x > kExpOverflow) return kInfinity;
  if (x < kExpUnderflow) return 0;
  const double k = std::round(x * kInverseLn2.hi);
  // x - k kLn2High is exact (Sterbenz, or k = 0).
  const DD r = two_sum(x - k * kLn2High, 0) - two_product(k, kLn2Middle) - dd(k * kLn2Low);
  return std::ldexp(rounded(horner(kExp, r)), static_cast<int>(k));
}

double log2(double x) {
  if (std::isnan(x) || x < 0) return kNaN;
  if (x == 0) return -kInfinity;
  if (std::isinf(x)) return x;
  const Split s = split_mantissa(x);
  return rounded(dd(s.e) + log_mantissa(s.m) * kInverseLn2);
}

namespace {

// The float functions' fast path: the kernels' series in plain double on the
// reduced argument, whose relative error (a few ulp of double, 2^-50) is far
// below kFloatMargin. Where the whole interval value (1 +- kFloatMargin)
// rounds to one float, so do the true value and the correctly rounded double
// (rounding is monotonic), so the float is the exact path's; elsewhere
// (about one argument in 2^16) the exact path decides. The same bits, at a
// fraction of the double-double kernels' cost (the path tracer draws two a
// bounce).
constexpr double kFloatMargin = 0x1p-40;

template <std::size_t N>
double horner_double(const std::array<DD, N>& c, double z) {
  double sum = c[N - 1].hi;
  for (std::size_t i = N - 1; i-- > 0;) sum = sum * z + c[i].hi;
  return sum;
}

// The float nearest `approx`, or NaN where the margin around it holds a
// rounding boundary.
float float_if_clear(double approx) {
  const float f = static_cast<float>(approx);
  const float low = static_cast<float>(approx - std::fabs(approx) * kFloatMargin);
  const float high = static_cast<float>(approx + std::fabs(approx) * kFloatMargin);
  return low == f && high == f ? f : std::numeric_limits<float>::quiet_NaN();
}

// sin (cosine = false) or cos of a finite float x, by the fast path.
float fast_sin_or_cos(float x, bool cosine) {
  const Reduced a = reduce_half_pi(static_cast<double>(x));
  const double r = a.r.hi, z = r * r;
  const bool use_cos = (a.quadrant % 2 == 1) != cosine;
  const double value = use_cos ? horner_double(kCos, z) : r + r * z * horner_double(kSin, z);
  const bool negate = cosine ? (a.quadrant == 1 || a.quadrant == 2) : a.quadrant >= 2;
  return float_if_clear(negate ? -value : value);
}

}  // namespace

float sin(float x) {
  if (x != 0 && std::isfinite(x)) {
    const float fast = fast_sin_or_cos(x, false);
    if (!std::isnan(fast)) return fast;
  }
  return static_cast<float>(sin(static_cast<double>(x)));
}
float cos(float x) {
  if (std::isfinite(x)) {
    const float fast = fast_sin_or_cos(x, true);
    if (!std::isnan(fast)) return fast;
  }
  return static_cast<float>(cos(static_cast<double>(x)));
}
float tan(float x) { return static_cast<float>(tan(static_cast<double>(x))); }

float pow(float x, float y) {
  if (y == 0 || x == 1) return 1;
  if (std::isnan(x) || std::isnan(y)) return static_cast<float>(kNaN);
  const double base = x, exponent = y;
  const bool negate = std::signbit(base) && is_odd_integer(exponent);
  if (base < 0 && std::trunc(exponent) != exponent) return static_cast<float>(kNaN);
  const double magnitude = std::fabs(base);
  double result;
  if (magnitude == 0) {
    result = exponent < 0 ? kInfinity : 0;
  } else if (std::isinf(magnitude)) {
    result = exponent < 0 ? 0 : kInfinity;
  } else {
    // y ln|x| to double precision is far more than a float result needs.
    const Split s = split_mantissa(magnitude);
    const double ln = s.e * kLn2High + (rounded(log_mantissa(s.m)) + s.e * kLn2Middle);
    result = exp(exponent * ln);
  }
  return static_cast<float>(negate ? -result : result);
}

}  // namespace nodetrace::base::portable_math
