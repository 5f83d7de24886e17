#include "geometry/triangulation.h"

#include <random>

#include <gtest/gtest.h>


namespace slamcmp {
namespace {

std::vector<SE3> cameraPath(int n) {
  std::vector<SE3> poses;
  for (int k = 0; k < n; ++k)
    poses.push_back(SE3::fromRotvec(Vec3(0.02 * k, -0.03 * k, 0.01), Vec3(0.03 * k, 0.01 * std::sin(k), -0.5 + 0.01 * k)));
  return poses;
}

std::vector<Ray> raysTo(const Vec3& p_world, const std::vector<SE3>& poses, double noise, std::mt19937* rng) {
  std::normal_distribution<double> n(0, noise);
  std::vector<Ray> rays;
  for (const SE3& T : poses) {
    const Vec2 xy = (T.inverse() * p_world).hnormalized() + Vec2(n(*rng), n(*rng));
    rays.push_back(rayFromObservation(T, xy));
  }
  return rays;
}

// Each method's point from all the rays, added one at a time.
template <class Method>
std::optional<Vec3> triangulate(const std::vector<Ray>& rays) {
  Method method;
  for (const Ray& ray : rays) method.add(ray);
  return method.solve();
}

TEST(Triangulation, BothMethodsAreExactOnExactRays) {
  std::mt19937 rng(1);
  for (const Vec3& p : {Vec3(0.1, 0.2, 1.0), Vec3(-0.4, 0.3, 2.5), Vec3(0.0, -0.2, 0.4)}) {
    const auto rays = raysTo(p, cameraPath(12), 0, &rng);
    const auto a = triangulate<RayMidpointAverage>(rays);
    const auto b = triangulate<RayLeastSquares>(rays);
    ASSERT_TRUE(a && b);
    EXPECT_LT((*a - p).norm(), 1e-9);
    EXPECT_LT((*b - p).norm(), 1e-9);
  }
}

TEST(Triangulation, ClosestPointsOfSkewAndParallelLines) {
  Vec3 a, b;
  const Ray x_axis{Vec3::Zero(), Vec3::UnitX()};
  const Ray skewed{Vec3(2, 0, 1), Vec3::UnitY()};
  ASSERT_TRUE(closestPointsOfRays(x_axis, skewed, &a, &b));
  EXPECT_LT((a - Vec3(2, 0, 0)).norm(), 1e-15);
  EXPECT_LT((b - Vec3(2, 0, 1)).norm(), 1e-15);
  EXPECT_FALSE(closestPointsOfRays(x_axis, Ray{Vec3(0, 1, 0), Vec3::UnitX()}, &a, &b));
  EXPECT_FALSE(triangulate<RayLeastSquares>({x_axis, Ray{Vec3(0, 1, 0), Vec3::UnitX()}}));
  EXPECT_FALSE(triangulate<RayMidpointAverage>({x_axis}));
}

// 0.5 px noise at f = 500 over 12 views spanning 33 cm at 1 to 2.5 m: a few millimetres to a
// couple of centimetres of depth error; both methods within 1 % of the depth.
TEST(Triangulation, NoisyRaysWithinTheNoise) {
  std::mt19937 rng(2);
  for (const Vec3& p : {Vec3(0.1, 0.2, 1.0), Vec3(-0.4, 0.3, 2.5)}) {
    double err_a = 0, err_b = 0;
    for (int trial = 0; trial < 50; ++trial) {
      const auto rays = raysTo(p, cameraPath(12), 0.5 / 500, &rng);
      err_a += (*triangulate<RayMidpointAverage>(rays) - p).squaredNorm();
      err_b += (*triangulate<RayLeastSquares>(rays) - p).squaredNorm();
    }
    EXPECT_LT(std::sqrt(err_a / 50), 0.01 * (p.z() + 0.5));
    EXPECT_LT(std::sqrt(err_b / 50), 0.01 * (p.z() + 0.5));
  }
}

}  // namespace
}  // namespace slamcmp
