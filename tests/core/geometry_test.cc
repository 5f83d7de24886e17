#include "core/geometry.h"

#include <cmath>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

TEST(Geometry, RotvecRoundTripNearZeroAndPi) {
  for (double angle : {0.0, 1e-10, 1e-5, 0.3, 2.0, M_PI - 1e-6, M_PI}) {
    const Vec3 r = angle * Vec3(1, -2, 0.5).normalized();
    const Vec3 back = rotvecFromRotation(rotationFromRotvec(r));
    // Near pi, r and -r are the same rotation.
    const double err = std::min((back - r).norm(), (back + r).norm());
    EXPECT_LT(err, 1e-8) << "angle " << angle;
  }
}

}  // namespace
}  // namespace slamcmp
