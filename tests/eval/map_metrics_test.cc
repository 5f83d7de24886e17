// Map accuracy statistics: hand-computed on a few errors, and the real room scene read back from
// scene.yaml scores points on its surfaces as zero and points pushed off the board as the push.
#include "eval/metrics/map_metrics.h"

#include <cmath>

#include <gtest/gtest.h>

#include "datasets/room_scene.h"
#include "eval/metrics/scene_distance.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

TEST(MapMetrics, StatisticsHandComputed) {
  const MapErrorStats s = mapErrorStats({0.002, 0.02, 0.004, 0.006});
  EXPECT_EQ(s.distance.count, 4);
  EXPECT_NEAR(s.distance.median, 0.005, 1e-15);
  EXPECT_NEAR(s.distance.max, 0.02, 1e-15);
  EXPECT_NEAR(s.distance.rmse, std::sqrt((4 + 400 + 16 + 36) * 1e-6 / 4), 1e-15);
  EXPECT_NEAR(s.within_1cm, 0.75, 1e-15);
  EXPECT_NEAR(mapErrorStats({0.01, 0.03, 0.02}).distance.median, 0.02, 1e-15);
  EXPECT_NEAR(mapErrorStats({0.01, 0.03, 0.02}).within_1cm, 1.0 / 3, 1e-15);  // 1 cm itself is within
}

TEST(MapMetrics, EmptyMapHasNoStatistics) {
  const MapErrorStats s = mapErrorStats({});
  EXPECT_EQ(s.distance.count, 0);
  EXPECT_TRUE(std::isnan(s.distance.median));
  const nlohmann::json j = mapStatsToJson(s);
  EXPECT_EQ(j["points"], 0);
  for (const char* key : {"rmse", "median", "max", "within_1cm"}) EXPECT_TRUE(j[key].is_null()) << key;
}

TEST(MapMetrics, RoomSceneThroughSceneYaml) {
  test::TempDir dir;
  const Scene scene = buildRoomScene(1);
  writeSceneYaml(dir.file("scene.yaml"), scene);
  const SceneGeometry geometry = readSceneYaml(dir.file("scene.yaml"));
  ASSERT_EQ(geometry.surfaces.size(), scene.surfaces.size());

  // Every surface's centre and corners lie on the scene; points 5 mm in front of the board's
  // inner squares are 5 mm off (the board faces -z).
  std::vector<MapPoint> map;
  for (const SceneSurface& s : sceneSurfaces(geometry))
    for (const Vec3& p : {Vec3(s.origin + 0.5 * (s.edge_u + s.edge_v)), s.origin, Vec3(s.origin + s.edge_u),
                          Vec3(s.origin + s.edge_u + s.edge_v)})
      map.push_back({static_cast<int>(map.size()), p, 1, -1});
  const size_t on_surface = map.size();
  const double square = scene.target.square_size;
  for (int i = 0; i < 3; ++i) map.push_back({static_cast<int>(map.size()), Vec3(i * square, square, -0.005), 1, -1});

  const MapEvaluation e = evaluateMap(map, geometry);
  ASSERT_EQ(e.errors.size(), map.size());
  for (size_t i = 0; i < on_surface; ++i) EXPECT_NEAR(e.errors[i], 0.0, 1e-12) << i;
  for (size_t i = on_surface; i < map.size(); ++i) {
    EXPECT_NEAR(e.errors[i], 0.005, 1e-12) << i;
    EXPECT_EQ(e.nearest[i], 0) << "the board";
  }
  EXPECT_EQ(e.stats.distance.count, static_cast<int>(map.size()));
  EXPECT_NEAR(e.stats.distance.max, 0.005, 1e-12);
  EXPECT_NEAR(e.stats.within_1cm, 1.0, 1e-15);
  const nlohmann::json j = mapStatsToJson(e.stats);
  EXPECT_NEAR(j["max"].get<double>(), 0.005, 1e-12);
}

TEST(MapMetrics, KnownPointsAreDrawnButNotScored) {
  SceneGeometry scene;
  scene.board = {"board", Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, -1)};
  const std::vector<MapPoint> map = {{0, Vec3(0.5, 0.5, 0.0), 0, 0.0},    // known: sigma exactly 0
                                     {1, Vec3(0.5, 0.5, 0.002), 5, 0.01},  // estimated, 2 mm off
                                     {2, Vec3(0.5, 0.5, -0.004), 5, -1}};  // sigma unknown, 4 mm off
  const MapEvaluation e = evaluateMap(map, scene);
  ASSERT_EQ(e.errors.size(), 3u);
  EXPECT_NEAR(e.errors[0], 0.0, 1e-15);
  EXPECT_EQ(e.stats.distance.count, 2);
  EXPECT_EQ(e.stats.known, 1);
  EXPECT_NEAR(e.stats.distance.median, 0.003, 1e-12);
  EXPECT_EQ(mapStatsToJson(e.stats)["known"].get<int>(), 1);
}

TEST(MapMetrics, SceneFileOfASequenceFolder) {
  test::TempDir dir;
  EXPECT_EQ(sceneFileOf(dir.path()), "");
  test::writeText(dir.file("scene.yaml"), "x");
  EXPECT_EQ(sceneFileOf(dir.path()), dir.file("scene.yaml"));
  EXPECT_EQ(sceneFileOf(dir.file("scene.yaml")), "");  // a file (e.g. a video) has none beside it
}

}  // namespace
}  // namespace slamcmp
