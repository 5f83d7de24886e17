#include "cslam/feature_map.h"

#include <random>

#include <gtest/gtest.h>

#include "cslam/feature_map.h"

namespace slamcmp {
namespace {

std::vector<SE3> cameraPath(int n) {
  std::vector<SE3> poses;
  for (int k = 0; k < n; ++k)
    poses.push_back(SE3::fromRotvec(Vec3(0.02 * k, -0.03 * k, 0.01), Vec3(0.03 * k, 0.01 * std::sin(k), -0.5 + 0.01 * k)));
  return poses;
}

TEST(FeatureMap, PointsBecomeUsableWithParallaxAndMatchBothMethods) {
  const Vec3 p(0.2, 0.1, 1.0);
  for (const std::string method : {"least_squares", "midpoint_average"}) {
    FeatureMapOptions options;
    options.method = method;
    options.min_parallax_deg = 3.0;
    FeatureMap map(options, 500);
    const auto poses = cameraPath(12);
    for (size_t k = 0; k < poses.size(); ++k) {
      map.addObservation(7, poses[k], (poses[k].inverse() * p).hnormalized());
      const double parallax_deg =
          std::acos(rayFromObservation(poses[0], (poses[0].inverse() * p).hnormalized())
                        .direction.dot(rayFromObservation(poses[k], (poses[k].inverse() * p).hnormalized()).direction)) *
          180 / M_PI;
      EXPECT_EQ(map.position(7).has_value(), parallax_deg >= 3.0) << method << " view " << k;
    }
    ASSERT_TRUE(map.position(7));
    EXPECT_LT((*map.position(7) - p).norm(), 1e-9) << method;
    ASSERT_EQ(map.points().size(), 1u);
    EXPECT_EQ(map.points()[0].observations, 12);
  }
}

TEST(FeatureMap, InconsistentRaysAreNotUsed) {
  FeatureMap map({}, 500);
  const auto poses = cameraPath(12);
  for (size_t k = 0; k < poses.size(); ++k) {
    // A track jumping 5 px up and down across the motion: its rays do not meet.
    const Vec2 xy = (poses[k].inverse() * Vec3(0.2, 0.1, 1.0)).hnormalized() + Vec2(0, 0.01 * (k % 2));
    map.addObservation(3, poses[k], xy);
  }
  EXPECT_FALSE(map.position(3));
  EXPECT_EQ(map.numUsable(), 0);
}

}  // namespace
}  // namespace slamcmp
