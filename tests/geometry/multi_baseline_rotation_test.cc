#include "geometry/multi_baseline_rotation.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/error.h"

namespace slamcmp {
namespace {

constexpr double kDegree = M_PI / 180;
constexpr double kFocal = 520;  // pixels: tum_fr1_rpy's

double angleDeg(const Mat3& A, const Mat3& B) { return rotationAngle(A.transpose() * B) / kDegree; }

// A hand-held camera turning about a point 8 cm behind it (tum_fr1_rpy's ground truth fits 7.8 cm):
// frame k pans and tilts by a few degrees a frame, and the camera swings with the turn.
struct Swing {
  std::vector<Vec3> p_world;  // a room 1-3 m in front
  std::vector<Mat3> R_world_camera;
  std::vector<Vec3> p_world_camera;  // centres

  explicit Swing(int frames, int points = 300, int seed = 1) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < points; ++i) p_world.emplace_back(1.5 * u(rng), 1.0 * u(rng), 2.0 + u(rng));
    for (int k = 0; k < frames; ++k) {
      const Mat3 R = rotationFromRotvec(Vec3(0.03 * std::sin(0.3 * k), 0.04 * k, 0.01 * k));
      R_world_camera.push_back(R);
      p_world_camera.push_back(R * Vec3(0, 0, 0.08));  // the pivot at the origin, behind the camera
    }
  }
  // Frame k's tracks: every point in front and within a 60-degree view, with pixel noise.
  FrameTracks tracks(int k, double noise_px = 0, std::mt19937* rng = nullptr) const {
    FrameTracks out;
    std::normal_distribution<double> n(0, noise_px / kFocal);
    for (size_t i = 0; i < p_world.size(); ++i) {
      const Vec3 p_camera = R_world_camera[k].transpose() * (p_world[i] - p_world_camera[k]);
      if (p_camera.z() < 0.3) continue;
      Vec2 xy = p_camera.hnormalized();
      if (std::abs(xy.x()) > 0.6 || std::abs(xy.y()) > 0.45) continue;
      if (rng) xy += Vec2(n(*rng), n(*rng));
      out.emplace_back(static_cast<int>(i), xy);
    }
    return out;
  }
};

// The rotation between two views estimated with the translation is the swing's turn; a rotation
// fitted alone turns further, the camera's step across the view taken for more turn.
TEST(MultiBaselineRotation, ASwingIsMeasuredAsItsTurnNotMore) {
  const Swing swing(11);
  MultiBaselineRotation rotation(MultiBaselineRotationOptions{}, kFocal);
  for (int k = 0; k < 10; ++k) rotation.remember(swing.tracks(k), swing.R_world_camera[k]);
  int views = 0;
  const std::optional<Mat3> R = rotation.measure(swing.tracks(10), &views);
  ASSERT_TRUE(R);
  EXPECT_EQ(views, 10);
  EXPECT_LT(angleDeg(*R, swing.R_world_camera[10]), 1e-4);

  // The fit alone from frame 0 to 10 turns further, as the filter did on tum_fr1_rpy.
  std::vector<Vec3> a, b;
  const FrameTracks t0 = swing.tracks(0), t10 = swing.tracks(10);
  for (const auto& [id, xy] : t0)
    for (const auto& [id10, xy10] : t10)
      if (id == id10) a.push_back(xy.homogeneous().normalized()), b.push_back(xy10.homogeneous().normalized());
  const Mat3 R_fit = rotationOnlyFit(a, b);
  const Mat3 R_true = swing.R_world_camera[10].transpose() * swing.R_world_camera[0];
  const double turn = rotationAngle(R_true) / kDegree;
  EXPECT_GT(rotationAngle(R_fit) / kDegree, 1.02 * turn);
  EXPECT_GT(angleDeg(R_fit, R_true), 0.02 * turn);
}

// Half a pixel of noise on every view's tracks: the mean of the views within 0.1 degrees (0.055
// measured).
TEST(MultiBaselineRotation, NoisyTracksAverageOverTheViews) {
  const Swing swing(11);
  std::mt19937 rng(7);
  MultiBaselineRotation rotation(MultiBaselineRotationOptions{}, kFocal);
  for (int k = 0; k < 10; ++k) rotation.remember(swing.tracks(k, 0.5, &rng), swing.R_world_camera[k]);
  const std::optional<Mat3> R = rotation.measure(swing.tracks(10, 0.5, &rng));
  ASSERT_TRUE(R);
  EXPECT_LT(angleDeg(*R, swing.R_world_camera[10]), 0.1);  // 0.055 measured
}

// A tenth of the current frame's tracks 5-15 px off in any direction (Lucas-Kanade's mistakes)
// barely pull the motion: the Cauchy loss. Fitted by least squares they turn it over 0.2 degrees.
TEST(MultiBaselineRotation, TracksFarOffTheMotionBarelyPullIt) {
  const Swing swing(11);
  auto measureWith = [&](double max_error_px) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> length(5 / kFocal, 15 / kFocal), direction(-M_PI, M_PI);
    MultiBaselineRotationOptions options;
    options.max_error_px = max_error_px;
    MultiBaselineRotation rotation(options, kFocal);
    for (int k = 0; k < 10; ++k) rotation.remember(swing.tracks(k), swing.R_world_camera[k]);
    FrameTracks now = swing.tracks(10);
    for (size_t i = 0; i < now.size(); i += 10) {
      const double a = direction(rng);
      now[i].second += length(rng) * Vec2(std::cos(a), std::sin(a));
    }
    const std::optional<Mat3> R = rotation.measure(now);
    return R ? angleDeg(*R, swing.R_world_camera[10]) : 180.0;
  };
  EXPECT_LT(measureWith(1.0), 0.05);
  EXPECT_GT(measureWith(1e6), 0.2);  // a scale beyond every residual: least squares
}

// Earlier orientations carry into the measurement: the views' frames are the filter's.
TEST(MultiBaselineRotation, ComposesWithTheRememberedOrientations) {
  const Swing swing(4);
  const Mat3 offset = rotationFromRotvec(Vec3(0.1, -0.2, 0.05));
  MultiBaselineRotation rotation(MultiBaselineRotationOptions{}, kFocal);
  for (int k = 0; k < 3; ++k) rotation.remember(swing.tracks(k), offset * swing.R_world_camera[k]);
  const std::optional<Mat3> R = rotation.measure(swing.tracks(3));
  ASSERT_TRUE(R);
  EXPECT_LT(angleDeg(*R, offset * swing.R_world_camera[3]), 1e-4);
}

TEST(MultiBaselineRotation, TooFewSharedTracksIsNoMeasurement) {
  const Swing swing(2, 300);
  MultiBaselineRotationOptions options;
  MultiBaselineRotation rotation(options, kFocal);
  int views = -1;
  EXPECT_FALSE(rotation.measure(swing.tracks(1), &views));  // nothing remembered
  EXPECT_EQ(views, 0);
  FrameTracks first = swing.tracks(0);
  first.resize(options.min_shared - 1);
  rotation.remember(first, Mat3::Identity());
  EXPECT_FALSE(rotation.measure(swing.tracks(1)));
  rotation.clear();
  rotation.remember(swing.tracks(0), Mat3::Identity());
  EXPECT_TRUE(rotation.measure(swing.tracks(1)));
}

// Only the last max_gap views are kept: each remembered orientation is off by its own turn about
// the world's z, and the measurement is off by the mean of the last three (4, 5, 6: 0.05 rad).
TEST(MultiBaselineRotation, KeepsTheLastMaxGapViews) {
  const Swing swing(8);
  MultiBaselineRotationOptions options;
  options.max_gap = 3;
  MultiBaselineRotation rotation(options, kFocal);
  for (int k = 0; k < 7; ++k)
    rotation.remember(swing.tracks(k), rotationFromRotvec(Vec3(0, 0, 0.01 * k)) * swing.R_world_camera[k]);
  int views = 0;
  const std::optional<Mat3> R = rotation.measure(swing.tracks(7), &views);
  ASSERT_TRUE(R);
  EXPECT_EQ(views, 3);
  EXPECT_LT(angleDeg(*R, rotationFromRotvec(Vec3(0, 0, 0.05)) * swing.R_world_camera[7]), 1e-3);
}

TEST(MultiBaselineRotation, OptionsAreChecked) {
  MultiBaselineRotationOptions options;
  options.max_gap = 0;
  EXPECT_THROW(options.check(), OptionError);
  options = MultiBaselineRotationOptions{};
  options.min_shared = 7;
  EXPECT_THROW(options.check(), OptionError);
  options = MultiBaselineRotationOptions{};
  options.max_error_px = 0;
  EXPECT_THROW(options.check(), OptionError);
  options = MultiBaselineRotationOptions{};
  options.refine_iterations = 0;
  EXPECT_THROW(options.check(), OptionError);
  options = MultiBaselineRotationOptions{};
  options.max_rotation_disagreement_deg = 0;
  EXPECT_THROW(options.check(), OptionError);
  options = MultiBaselineRotationOptions{};
  options.max_spread_deg = -1;
  EXPECT_THROW(options.check(), OptionError);
  EXPECT_NO_THROW(MultiBaselineRotationOptions{}.check());
  EXPECT_THROW(MultiBaselineRotation(MultiBaselineRotationOptions{}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace slamcmp
