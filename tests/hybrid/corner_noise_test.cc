// The board corners' noise estimated from their scatter about the board plane's homography
// (hybrid/corner_noise.h): the known noise of simulated views, recovered with its degrees of
// freedom; its floor; a change of noise followed within a few time constants.
#include "hybrid/corner_noise.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "core/error.h"
#include "geometry/homography_pose.h"

namespace slamcmp {
namespace {

constexpr double kFocalPx = 500;

// One view of a 4x3 grid of corners (12: 16 degrees of freedom beyond the homography's 8, so a
// count that forgot them would be off by sqrt(24 / 16)), each axis off by `sigma_px`: the corners'
// distances to the homography fitted through them, pixels.
std::vector<double> viewErrors(double sigma_px, std::mt19937& rng) {
  std::normal_distribution<double> noise(0, sigma_px / kFocalPx);
  Mat3 H;
  H << 0.9, 0.1, -0.1, -0.05, 1.1, -0.08, 0.2, 0.1, 1.0;  // a board seen at a slant
  std::vector<Vec2> plane, xy;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) {
      plane.emplace_back(0.04 * i, 0.04 * j);
      xy.push_back((H * plane.back().homogeneous()).hnormalized() + Vec2(noise(rng), noise(rng)));
    }
  std::vector<double> errors = homographyErrors(homographyDlt(plane, xy), plane, xy);
  for (double& e : errors) e *= kFocalPx;
  return errors;
}

CornerNoiseOptions estimating(double time_constant_frames) {
  CornerNoiseOptions options;
  options.enabled = true;
  options.time_constant_frames = time_constant_frames;
  return options;
}

TEST(CornerNoise, RecoversTheNoiseOfSimulatedViews) {
  std::mt19937 rng(3);
  for (const double sigma : {0.05, 0.3}) {
    CornerNoise noise(estimating(1000), 0.2);
    for (int view = 0; view < 500; ++view) noise.add(viewErrors(sigma, rng));
    // 8000 degrees of freedom: the estimate within 1 % (one standard deviation); 4 % allowed.
    EXPECT_NEAR(noise.pixelSigma(), sigma, 0.04 * sigma);
  }
}

TEST(CornerNoise, SetValueUntilEnoughIsPooledAndWhenOff) {
  std::mt19937 rng(4);
  CornerNoise noise(estimating(30), 0.2);
  noise.add(viewErrors(0.05, rng));  // 16 degrees of freedom, under min_dof (40)
  EXPECT_EQ(noise.pixelSigma(), 0.2);
  noise.add({1.0, 1.0, 1.0, 1.0});  // four corners hold none beyond the homography's
  EXPECT_EQ(noise.pixelSigma(), 0.2);
  for (int view = 0; view < 3; ++view) noise.add(viewErrors(0.05, rng));
  EXPECT_NEAR(noise.pixelSigma(), 0.05, 0.02);

  CornerNoiseOptions off_options;
  off_options.enabled = false;
  CornerNoise off(off_options, 0.2);
  for (int view = 0; view < 10; ++view) off.add(viewErrors(0.05, rng));
  EXPECT_EQ(off.pixelSigma(), 0.2);
}

TEST(CornerNoise, KeptAtItsFloor) {
  std::mt19937 rng(5);
  CornerNoise noise(estimating(30), 0.2);
  for (int view = 0; view < 50; ++view) noise.add(viewErrors(0.002, rng));
  EXPECT_EQ(noise.pixelSigma(), CornerNoiseOptions{}.min_pixel_sigma);
}

TEST(CornerNoise, FollowsAChangeOfNoise) {
  std::mt19937 rng(6);
  CornerNoise noise(estimating(10), 0.2);
  for (int view = 0; view < 100; ++view) noise.add(viewErrors(0.1, rng));
  for (int view = 0; view < 50; ++view) noise.add(viewErrors(0.3, rng));  // five time constants
  // The old views weigh exp(-5) of the new ones: 0.3 within 1 %, 160 degrees of freedom (6 %).
  EXPECT_NEAR(noise.pixelSigma(), 0.3, 0.05);
}

TEST(CornerNoise, RefusesABadFloorOrTimeConstant) {
  CornerNoiseOptions options;
  options.min_pixel_sigma = 0;
  EXPECT_THROW(options.check(), OptionError);
  options = CornerNoiseOptions{};
  options.time_constant_frames = 0.5;
  EXPECT_THROW(options.check(), OptionError);
  options = CornerNoiseOptions{};
  options.min_dof = 0;
  EXPECT_THROW(options.check(), OptionError);
}

}  // namespace
}  // namespace slamcmp
