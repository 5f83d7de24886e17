// Point-to-surface distance against hand-computed cases: inside a rectangle it is the distance to
// its plane, beyond an edge or corner the distance to that edge or corner (never to the infinite
// plane), for tilted and skewed surfaces too.
#include "eval/metrics/scene_distance.h"

#include <cmath>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

SceneSurface surface(const Vec3& origin, const Vec3& u, const Vec3& v) {
  SceneSurface s;
  s.name = "s";
  s.origin = origin;
  s.edge_u = u;
  s.edge_v = v;
  s.normal = u.cross(v).normalized();
  return s;
}

const SceneSurface kUnitSquare = surface(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0));

TEST(SceneDistance, UnitSquareHandComputed) {
  EXPECT_NEAR(distanceToSurface(Vec3(0.5, 0.5, 2), kUnitSquare), 2.0, 1e-15);     // above the inside
  EXPECT_NEAR(distanceToSurface(Vec3(0.25, 0.75, -0.3), kUnitSquare), 0.3, 1e-15);  // the back side
  EXPECT_NEAR(distanceToSurface(Vec3(0.5, 0.5, 0), kUnitSquare), 0.0, 1e-15);
  EXPECT_NEAR(distanceToSurface(Vec3(1, 1, 0), kUnitSquare), 0.0, 1e-15);         // a corner itself
  EXPECT_NEAR(distanceToSurface(Vec3(2, 0.5, 0), kUnitSquare), 1.0, 1e-15);       // in plane, beyond x = 1
  EXPECT_NEAR(distanceToSurface(Vec3(1.5, 0.5, 1), kUnitSquare), std::sqrt(1.25), 1e-15);  // edge x = 1
  EXPECT_NEAR(distanceToSurface(Vec3(2, 3, 0), kUnitSquare), std::sqrt(5.0), 1e-15);       // corner (1, 1)
  EXPECT_NEAR(distanceToSurface(Vec3(-1, -2, 2), kUnitSquare), 3.0, 1e-15);               // corner (0, 0)
  EXPECT_NEAR(distanceToSurface(Vec3(0.5, -0.4, -0.3), kUnitSquare), 0.5, 1e-15);         // edge y = 0
}

TEST(SceneDistance, TiltedRectangle) {
  // 2 m x 0.5 m, turned 30 degrees about z and moved: hand-built points in its own frame.
  const Vec3 o(1, 2, 3), u_hat(std::cos(M_PI / 6), std::sin(M_PI / 6), 0), v_hat(0, 0, 1);
  const Vec3 n_hat = u_hat.cross(v_hat);
  const SceneSurface s = surface(o, 2 * u_hat, 0.5 * v_hat);
  EXPECT_NEAR(distanceToSurface(o + 1.0 * u_hat + 0.25 * v_hat + 0.7 * n_hat, s), 0.7, 1e-12);
  EXPECT_NEAR(distanceToSurface(o - 0.3 * u_hat + 0.25 * v_hat, s), 0.3, 1e-12);
  EXPECT_NEAR(distanceToSurface(o + 2.4 * u_hat + 0.8 * v_hat - 1.2 * n_hat, s), std::sqrt(0.16 + 0.09 + 1.44),
              1e-12);
}

TEST(SceneDistance, SkewedParallelogramAndDegenerateSurfaces) {
  // Edges (1, 0, 0) and (1, 1, 0): (1, 0.5) is inside (a = b = 0.5), (0, 0.5) is beyond the edge
  // along (1, 1) at 0.5 / sqrt(2).
  const SceneSurface p = surface(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0));
  EXPECT_NEAR(distanceToSurface(Vec3(1, 0.5, 0.4), p), 0.4, 1e-15);
  EXPECT_NEAR(distanceToSurface(Vec3(0, 0.5, 0), p), 0.5 / std::sqrt(2.0), 1e-15);
  // A zero edge leaves a segment; two zero edges a point.
  const SceneSurface segment = surface(Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 0));
  EXPECT_NEAR(distanceToSurface(Vec3(0.5, 3, 4), segment), 5.0, 1e-15);
  const SceneSurface point = surface(Vec3(1, 1, 1), Vec3(0, 0, 0), Vec3(0, 0, 0));
  EXPECT_NEAR(distanceToSurface(Vec3(1, 4, 5), point), 5.0, 1e-15);
}

TEST(SceneDistance, NearestOfSeveral) {
  SceneGeometry scene;
  scene.board = kUnitSquare;
  scene.surfaces = {surface(Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0, 1, 0)),   // parallel, 1 m above
                    surface(Vec3(3, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1))};  // a wall at x = 3
  const auto all = sceneSurfaces(scene);
  ASSERT_EQ(all.size(), 3u);
  NearestSurface n = nearestSurface(Vec3(0.5, 0.5, 0.7), all);
  EXPECT_EQ(n.index, 1);
  EXPECT_NEAR(n.distance, 0.3, 1e-15);
  n = nearestSurface(Vec3(2.9, 0.5, 0.5), all);
  EXPECT_EQ(n.index, 2);
  EXPECT_NEAR(n.distance, 0.1, 1e-15);
  n = nearestSurface(Vec3(0.5, 0.5, 0.2), all);
  EXPECT_EQ(n.index, 0);  // the board
  EXPECT_EQ(nearestSurface(Vec3(0, 0, 0), {}).index, -1);
}

}  // namespace
}  // namespace slamcmp
