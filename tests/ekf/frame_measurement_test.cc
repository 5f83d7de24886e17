#include "ekf/frame_measurement.h"

#include <gtest/gtest.h>

#include "core/image.h"
#include "ekf/ekf_update.h"

#include "tests/ekf/plane_render.h"

namespace slamcmp {
namespace {

// Nine points on the textured plane z = 1 seen by a camera at the origin, known exactly; the camera
// uncertain (quaternion std 5e-3: ellipses of about 15 px). Feature 4's template is anchored
// `slip_px` pixels right of where it lies, as a patch sliding along an occluding edge would match.
struct Scene {
  CameraModel camera = test::testCamera();
  cv::Mat grey;
  EkfState state;
  std::vector<MapFeature> features;
  explicit Scene(double slip_px) {
    grey = test::renderPlane(camera, SE3(), 1.0);
    Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Zero();
    P.diagonal().segment<3>(EkfState::kR).setConstant(1e-6);
    P.diagonal().segment<4>(EkfState::kQ).setConstant(2.5e-5);
    state.reset(SE3(), P);
    for (int i = 0; i < 9; ++i) {
      // The most textured pixel near each node of a 3x3 grid (the texture has flat spots).
      Vec2 uv;
      double best = 0;
      for (int step = 0; step < 36; ++step) {
        const Vec2 candidate(200 + 120 * (i % 3) + 6 * (step % 6), 160 + 80 * (i / 3) + 6 * (step / 6));
        PatchSource source;
        cv::Mat templ;
        if (makePatchSource(grey, candidate, 41, SE3(), &source) && sourceTemplate(source, 11, &templ) &&
            patchStdDev(templ) > best) {
          best = patchStdDev(templ);
          uv = candidate;
        }
      }
      MapFeature f;
      EXPECT_TRUE(makePatchSource(grey, uv, 41, SE3(), &f.source));
      const Vec2 xy = camera.undistortPixel(uv);
      f.id = i;
      f.offset = state.append(Vec3(xy.x(), xy.y(), 1.0), Mat3::Zero(), Eigen::MatrixXd::Zero(3, state.size()));
      features.push_back(f);
    }
    features[4].source.uv0.x() += slip_px;
  }
};

// The scene's features measured, each match tested against the others with this variance floor
// (ActiveSearchOptions::min_variance_factor; 0: with the covariance as assumed).
FrameMeasurement measureWithFloor(Scene& scene, double min_variance_factor) {
  ActiveSearchOptions options;
  options.min_variance_factor = min_variance_factor;
  return measureFeatures(scene.state, scene.features, scene.camera, scene.grey, options);
}

TEST(FrameMeasurement, AMatchTheOthersContradictIsDropped) {
  Scene scene(6.0);
  ActiveSearchOptions options;
  const FrameMeasurement m = measureFeatures(scene.state, scene.features, scene.camera, scene.grey, options);
  ASSERT_EQ(m.visible, 9);
  EXPECT_EQ(m.matched, 8);
  for (const FeatureSearch& s : m.features) {
    EXPECT_EQ(s.outcome, s.index == 4 ? SearchOutcome::Failed : SearchOutcome::Matched) << s.index;
    if (s.outcome == SearchOutcome::Matched) {
      EXPECT_LT((s.uv_matched - s.uv_predicted).norm(), 0.5);
    }
  }
  EXPECT_EQ(scene.features[4].successes, 0);
  EXPECT_EQ(scene.features[4].attempts, 1);
}

// The slip is inside feature 4's own ellipse: without the check it is used (and pulls the camera).
TEST(FrameMeasurement, WithoutTheConsistencyCheckTheSlippedMatchIsUsed) {
  Scene scene(6.0);
  ActiveSearchOptions options;
  options.consistency_gate = 1 - 1e-12;
  options.consistency_core_min = 0;
  options.joint_gate = 1 - 1e-12;
  const FrameMeasurement m = measureFeatures(scene.state, scene.features, scene.camera, scene.grey, options);
  EXPECT_EQ(m.matched, 9);
  EXPECT_GT(std::abs(scene.state.q()(2)), 1e-4);  // turned about y towards the slipped match
}

// A 3 px slip hides among matches found to a small fraction of the assumed 1 px (measured: slips
// of 2-3.5 px pass, 4 px is caught): the test with the assumed noise keeps it and the camera turns
// towards it; with the noise the other matches show (Pope's tau test, min_variance_factor) it is
// dropped and the camera stays put.
TEST(FrameMeasurement, ASmallSlipIsDroppedWithTheNoiseTheOthersShow) {
  for (double factor : {0.0, 0.1}) {
    SCOPED_TRACE(factor);
    Scene scene(3.0);
    const FrameMeasurement m = measureWithFloor(scene, factor);
    if (factor == 0) {
      EXPECT_EQ(m.matched, 9);
      EXPECT_GT(std::abs(scene.state.q()(2)), 1e-4);
    } else {
      EXPECT_EQ(m.matched, 8);
      EXPECT_EQ(scene.features[4].successes, 0);
      EXPECT_LT(std::abs(scene.state.q()(2)), 1e-5);
    }
  }
}

// Two matches slipped alike (two look-alikes off in the same direction, which one pose error
// explains: vamr_checkerboard frames 307 and 325) mask each other in the test of each against all
// the others, where one such slip alone is dropped (above): both are kept and the camera turns
// towards them. Tested also against the most consistent half of the others
// (consistency_core_min), both are dropped and the camera stays put. Measured: slips of 2-4 px
// masked, 5 px caught either way.
TEST(FrameMeasurement, TwoMatchesSlippedAlikeAreDroppedAgainstTheConsistentHalf) {
  for (int core_min : {0, 6}) {
    SCOPED_TRACE(core_min);
    Scene scene(0.0);
    for (int k : {2, 5}) scene.features[k].source.uv0.x() += 4.0;
    ActiveSearchOptions options;
    options.consistency_core_min = core_min;
    const FrameMeasurement m = measureFeatures(scene.state, scene.features, scene.camera, scene.grey, options);
    if (core_min == 0) {
      EXPECT_EQ(m.matched, 9);
      EXPECT_GT(std::abs(scene.state.q()(2)), 1e-4);
    } else {
      EXPECT_EQ(m.matched, 7);
      EXPECT_EQ(scene.features[2].successes + scene.features[5].successes, 0);
      EXPECT_LT(std::abs(scene.state.q()(2)), 1e-5);
    }
  }
}

// No slip: every point matches at its prediction and the camera stays put.
TEST(FrameMeasurement, ConsistentMatchesAreAllKept) {
  for (double factor : {0.0, 0.1}) {
    SCOPED_TRACE(factor);
    Scene scene(0.0);
    const FrameMeasurement m = measureWithFloor(scene, factor);
    EXPECT_EQ(m.matched, 9);
    EXPECT_LT(scene.state.r().norm(), 1e-4);
  }
}

// The matches' joint NIS is the prior's: nu^T S^-1 nu of the kept matches under the covariance
// before the update, recomputed here from the prior state. With the slip used (no consistency
// check) it is larger than without it; 1-point RANSAC computes none (dof 0).
TEST(FrameMeasurement, JointNisOfTheKeptMatchesBeforeTheUpdate) {
  const auto nisFromPrior = [](const EkfState& prior, const Scene& scene, const FrameMeasurement& m) {
    std::vector<PointObservation> kept;
    for (const FeatureSearch& s : m.features) {
      if (s.outcome != SearchOutcome::Matched) continue;
      PointObservation o;
      o.offset = scene.features[s.index].offset;
      EXPECT_TRUE(predictFeature(scene.camera, prior.x(), scene.features[s.index], &o.h));
      o.z = s.uv_matched;
      kept.push_back(o);
    }
    Eigen::VectorXd nu(2 * kept.size());
    for (size_t k = 0; k < kept.size(); ++k) nu.segment<2>(2 * k) = kept[k].z - kept[k].h.uv_distorted;
    return nu.dot(innovationCovariance(prior, kept, ActiveSearchOptions().pixel_sigma).ldlt().solve(nu));
  };
  Scene checked(6.0);
  const EkfState checked_prior = checked.state;
  const FrameMeasurement dropped = measureFeatures(checked.state, checked.features, checked.camera, checked.grey, {});
  ASSERT_EQ(dropped.matched, 8);
  EXPECT_EQ(dropped.nis_dof, 16);
  EXPECT_NEAR(dropped.nis, nisFromPrior(checked_prior, checked, dropped), 1e-9 * (1 + dropped.nis));

  Scene unchecked(6.0);
  const EkfState unchecked_prior = unchecked.state;
  ActiveSearchOptions loose;
  loose.consistency_gate = 1 - 1e-12;
  loose.consistency_core_min = 0;
  loose.joint_gate = 1 - 1e-12;
  const FrameMeasurement used = measureFeatures(unchecked.state, unchecked.features, unchecked.camera, unchecked.grey, loose);
  ASSERT_EQ(used.matched, 9);
  EXPECT_EQ(used.nis_dof, 18);
  EXPECT_NEAR(used.nis, nisFromPrior(unchecked_prior, unchecked, used), 1e-9 * (1 + used.nis));
  EXPECT_GT(used.nis, 10 * dropped.nis);  // the 6 px slip

  // 1-point RANSAC's kept matches (the low-innovation inliers and those rescued) score the same way,
  // against the prior before both of its updates: the 6 px slip is not among them.
  Scene ransac_scene(6.0);
  const EkfState ransac_prior = ransac_scene.state;
  OnePointRansacOptions ransac;
  std::mt19937 rng(1);
  const FrameMeasurement by_ransac = measureFeatures(ransac_scene.state, ransac_scene.features, ransac_scene.camera,
                                                     ransac_scene.grey, {}, &ransac, &rng);
  ASSERT_EQ(by_ransac.matched, 8);
  EXPECT_EQ(by_ransac.nis_dof, 16);
  EXPECT_NEAR(by_ransac.nis, nisFromPrior(ransac_prior, ransac_scene, by_ransac), 1e-9 * (1 + by_ransac.nis));
  EXPECT_LT(by_ransac.nis, used.nis / 10);
}

}  // namespace
}  // namespace slamcmp
