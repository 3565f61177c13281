// The elementary functions that decide a ray, a tree, a layout or a record,
// with results the project controls: the same bits on every CPU, compiler and
// C library. The C library's versions are not enough: glibc picks FMA or
// non-FMA code by CPU at run time, and its float functions differ by an ulp
// between x86-64 and arm64 (tanf does for some camera angles).
//
// Each is built from the four IEEE 754 operations, sqrt, frexp/ldexp and
// rounding to an integer, which are exact or correctly rounded everywhere,
// evaluated in a fixed order (the build turns off contraction into fused
// multiply-adds) in double-double arithmetic, and rounded once: the results
// are correctly rounded but where the true value lies within about 2^-40 ulp
// of a midpoint (within 0.5 ulp of long double on 10^5 random arguments per
// function: tests/base/test_portable_math.cpp). So they also
// agree with the C library wherever it rounds correctly, and old traces keep
// their bytes. The float overloads compute in double and round once.
// sin, cos and tan reduce arguments up to 2^19 pi/2 to about 120 bits;
// larger arguments are reduced modulo the double nearest 2 pi
// (deterministic, less accurate: no caller passes them).
#pragma once

#if defined(__FAST_MATH__)
#error "nodetrace needs IEEE 754 arithmetic: build without -ffast-math (same trace bytes on every machine)"
#endif
#if defined(__FLT_EVAL_METHOD__) && __FLT_EVAL_METHOD__ != 0
#error "nodetrace needs float and double arithmetic in their own precision (x87 excess precision would change traces): build 32-bit x86 with -msse2 -mfpmath=sse"
#endif

namespace nodetrace::base::portable_math {

double sin(double x);
double cos(double x);
double tan(double x);
double atan2(double y, double x);
double acos(double x);
double exp(double x);
double log2(double x);

float sin(float x);
float cos(float x);
float tan(float x);
// x^y for the Phong lobes: exp(y * ln x) in double, rounded to float.
float pow(float x, float y);

}  // namespace nodetrace::base::portable_math
