// The watertight test's per-ray axes (ShearedRay) are chosen without
// branches; they must be the axes of the plain rule: kz the largest
// |direction| component (x before y before z on ties, as strict compares
// give), kx and ky the next two in cyclic order, swapped when the
// direction's kz component is negative (the winding kept). The axes decide
// which triangle owns a shared edge, so traces depend on them bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>

#include "accel/watertight_intersection.hpp"

namespace nodetrace::tracer {
namespace {

struct Axes {
  int kx, ky, kz;
};

Axes plain_axes(const Vec3& d) {
  const float ax = std::fabs(d.x), ay = std::fabs(d.y), az = std::fabs(d.z);
  Axes axes{};
  axes.kz = ax > ay ? (ax > az ? 0 : 2) : (ay > az ? 1 : 2);
  axes.kx = (axes.kz + 1) % 3;
  axes.ky = (axes.kx + 1) % 3;
  const float dz = axes.kz == 0 ? d.x : axes.kz == 1 ? d.y : d.z;
  if (dz < 0) std::swap(axes.kx, axes.ky);
  return axes;
}

TEST(ShearedRayTest, AxesAreThoseOfThePlainRule) {
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float specials[] = {0.0f,  -0.0f, 1.0f, -1.0f, 0.5f, -0.5f, 1e-40f, -1e-40f, 1e30f, -1e30f,
                            kInf, -kInf, std::numeric_limits<float>::quiet_NaN()};
  std::mt19937 engine(5);
  std::uniform_real_distribution<float> uniform(-1.0f, 1.0f);
  int swapped = 0;
  for (int i = 0; i < 200000; ++i) {
    float c[3];
    for (float& component : c) {
      // Often a special value, often equal in size to another component (ties).
      const unsigned pick = engine() % 4;
      component = pick == 0 ? specials[engine() % std::size(specials)] : uniform(engine);
    }
    if (engine() % 4 == 0) c[engine() % 3] = (engine() % 2 ? 1.0f : -1.0f) * std::fabs(c[engine() % 3]);
    const Vec3 direction{c[0], c[1], c[2]};
    const detail::ShearedRay sheared(Ray{Vec3{1.0f, 2.0f, 3.0f}, direction});
    const Axes want = plain_axes(direction);
    ASSERT_EQ(sheared.kz, want.kz) << c[0] << " " << c[1] << " " << c[2];
    ASSERT_EQ(sheared.kx, want.kx) << c[0] << " " << c[1] << " " << c[2];
    ASSERT_EQ(sheared.ky, want.ky) << c[0] << " " << c[1] << " " << c[2];
    swapped += want.kx == (want.kz + 2) % 3;
  }
  EXPECT_GT(swapped, 0);  // the winding case was reached
}

}  // namespace
}  // namespace nodetrace::tracer
