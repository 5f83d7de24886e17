#include "ekf/msckf_update.h"

#include <random>

#include <gtest/gtest.h>

#include "tests/ekf/plane_render.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// A camera moving 4 mm and turning 0.3 degrees a frame past points 0.6-1.5 m away: the filter's
// state holds the current camera and the window's clones (the last one the current pose).
struct Window {
  CameraModel camera = test::testCamera();
  std::vector<SE3> T_world_camera;
  std::vector<Vec3> p_world;
  Window(int frames, int points, unsigned seed = 1) {
    for (int k = 0; k < frames; ++k)
      T_world_camera.emplace_back(quatFromRotvec(Vec3(0.02, -0.1 + 0.005 * k, 0.03)), Vec3(0.1 + 0.004 * k, -0.05, -0.9));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-0.35, 0.35), depth(0.6, 1.5);
    for (int i = 0; i < points; ++i) p_world.push_back(T_world_camera[0] * Vec3(u(rng), u(rng), depth(rng)));
  }
  // The state: the camera at the last frame and a clone of every frame, with the given errors
  // (position, rotation vector) on the last pose and its clone.
  EkfState state(const Vec3& dr, const Vec3& dtheta, double sigma_position, double sigma_quat) const {
    EkfState s;
    Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Identity() * 1e-12;
    s.reset(T_world_camera.back(), P);
    std::vector<int> clones;
    for (size_t k = 0; k < T_world_camera.size(); ++k) {
      s.x().head<3>() = T_world_camera[k].t();
      s.x().segment<4>(3) = quatVector(T_world_camera[k].quat());
      clones.push_back(cloneCameraPose(s));
    }
    // The last pose off by (dr, dtheta), uncertain; the camera is the same pose (fully correlated).
    const SE3 off(quatFromRotvec(dtheta) * T_world_camera.back().quat(), T_world_camera.back().t() + dr);
    Eigen::Matrix<double, 7, 1> pose;
    pose << off.t(), quatVector(off.quat());
    Eigen::Matrix<double, 7, 7> P_pose = Eigen::Matrix<double, 7, 7>::Zero();
    P_pose.diagonal() << Vec3::Constant(sigma_position * sigma_position), Vec4::Constant(sigma_quat * sigma_quat);
    for (int offset : {0, clones.back()}) s.x().segment<7>(offset) = pose;
    for (int a : {0, clones.back()})
      for (int b : {0, clones.back()}) s.P().block<7, 7>(a, b) = P_pose;
    return s;
  }
  std::vector<std::vector<CloneObservation>> tracks(const EkfState& s, double noise_px, unsigned seed) const {
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0, noise_px);
    const int first_clone = s.size() - s.tailSize();
    std::vector<std::vector<CloneObservation>> out;
    for (const Vec3& p : p_world) {
      std::vector<CloneObservation> track;
      for (size_t k = 0; k < T_world_camera.size(); ++k)
        track.push_back({first_clone + kCloneDim * static_cast<int>(k),
                         camera.project(T_world_camera[k].inverse() * p) + Vec2(n(rng), n(rng))});
      out.push_back(std::move(track));
    }
    return out;
  }
};

TEST(MsckfUpdate, TriangulatesATrackFromExactClonesAndRefusesTooLittleParallax) {
  const Window w(6, 3);
  const EkfState s = w.state(Vec3::Zero(), Vec3::Zero(), 1e-6, 1e-6);
  const auto tracks = w.tracks(s, 0, 1);
  MsckfOptions options;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const auto p = triangulateTrack(s, w.camera, tracks[i], options);
    ASSERT_TRUE(p);
    EXPECT_LT((*p - w.p_world[i]).norm(), 1e-9);
  }
  options.min_parallax_deg = 5;  // the window spans 2 cm at 0.6-1.5 m: about 1 degree
  EXPECT_FALSE(triangulateTrack(s, w.camera, tracks[0], options));
}

TEST(MsckfUpdate, ExactTracksPullTheLastPoseBackToTheTruth) {
  const Window w(6, 60);
  // The last pose 1.7 mm and 0.1 degrees off, the earlier clones exact.
  EkfState s = w.state(Vec3(0.001, -0.001, 0.001), Vec3(0.001, -0.001, 0.001), 0.003, 0.002);
  MsckfOptions options;
  options.max_triangulation_px = 10;  // the last pose, 1-2 px off, is in every triangulation
  const MsckfResult result = msckfUpdate(s, w.camera, w.tracks(s, 0, 1), options);
  ASSERT_TRUE(result.applied);
  EXPECT_EQ(result.used, 60);
  // One linearisation at points triangulated with the wrong pose: within 5 % of the error.
  const SE3& truth = w.T_world_camera.back();
  EXPECT_LT((s.r() - truth.t()).norm(), 0.05 * 0.0017);
  EXPECT_LT(rotationAngle(s.T_world_camera().R() * truth.R().transpose()), 0.05 * 0.0017);
  EXPECT_NEAR(s.q().norm(), 1, 1e-12);
  // The clone of the last pose moved with the camera, fully correlated with it.
  EXPECT_LT((s.x().segment<3>(s.size() - kCloneDim) - s.r()).norm(), 1e-9);
}

TEST(MsckfUpdate, AnOutlierTrackIsLeftOut) {
  const Window w(6, 30);
  EkfState s = w.state(Vec3::Zero(), Vec3::Zero(), 0.002, 0.001);
  auto tracks = w.tracks(s, 0.3, 2);
  tracks[4][3].uv += Vec2(6, -4);
  const MsckfResult result = msckfUpdate(s, w.camera, tracks, MsckfOptions{});
  EXPECT_EQ(result.rejected + result.untriangulated, 1);
  EXPECT_EQ(result.used, 29);
  // Beyond the triangulation's own test, the chi-squared gate.
  MsckfOptions loose;
  loose.max_triangulation_px = 20;
  EkfState again = w.state(Vec3::Zero(), Vec3::Zero(), 0.002, 0.001);
  const MsckfResult gated = msckfUpdate(again, w.camera, tracks, loose);
  EXPECT_EQ(gated.rejected, 1);
  EXPECT_EQ(gated.used, 29);
}

// Two frames, as hybrid uses them, with tracks at 0.05 px and the last pose known to 2 mm: a
// track whose last observation is 0.8 px off passes its own gate (the prior lets the pose explain
// 2 px) and pulls the pose; tested against the other tracks (data snooping, at Baarda's usual
// 0.999: at 0.99 one of 40 good tracks would fail a third of the time) it is the one left out.
TEST(MsckfUpdate, ATrackTheOthersContradictIsLeftOutBySnooping) {
  const Window w(2, 40);
  const Vec3 dr(0.001, -0.001, 0.0005);
  auto tracks = w.tracks(w.state(dr, Vec3::Zero(), 0.002, 0.001), 0.05, 3);
  tracks[7][1].uv += Vec2(0, 0.8);  // across its epipolar line (the camera moves along x)
  MsckfOptions options;
  options.pixel_sigma = 0.05;
  options.min_parallax_deg = 0;  // hybrid's: two frames 4 mm apart
  options.max_triangulation_px = 10;
  EkfState plain = w.state(dr, Vec3::Zero(), 0.002, 0.001);
  const MsckfResult gated = msckfUpdate(plain, w.camera, tracks, options);
  EXPECT_EQ(gated.rejected, 0);
  EXPECT_EQ(gated.used, 40);
  // The update without that track, and snooping's.
  auto without = tracks;
  without.erase(without.begin() + 7);
  EkfState reference = w.state(dr, Vec3::Zero(), 0.002, 0.001);
  msckfUpdate(reference, w.camera, without, options);
  options.snooping_probability = 0.999;
  EkfState snooped = w.state(dr, Vec3::Zero(), 0.002, 0.001);
  const MsckfResult result = msckfUpdate(snooped, w.camera, tracks, options);
  EXPECT_EQ(result.snooped, 1);
  EXPECT_EQ(result.used, 39);
  EXPECT_LT((snooped.x() - reference.x()).norm(), 1e-12);
  EXPECT_GT((plain.x() - reference.x()).norm(), 1e-4);  // the outlier's pull: measured 5e-4 (m and quaternion)
  // Without the outlier, snooping drops nothing.
  tracks[7][1].uv -= Vec2(0, 0.8);
  EkfState clean = w.state(dr, Vec3::Zero(), 0.002, 0.001);
  EXPECT_EQ(msckfUpdate(clean, w.camera, tracks, options).snooped, 0);
}

TEST(MsckfUpdate, TheLastPositionIsConsistentWithItsCovariance) {
  // Monte Carlo: the last pose's prior error drawn from its covariance, pixel noise at the
  // update's sigma; the position's NEES averaged over the runs must fall in its 99 % chi-squared
  // bounds (3 dof x 200 runs: 2.57 to 3.46).
  const Window w(6, 40);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0, 1);
  const double sigma_position = 0.001, sigma_angle = 0.0005;  // a filter's pose after the board's update
  double nees = 0;
  const int runs = 200;
  MsckfOptions options;
  options.pixel_sigma = 0.5;
  options.max_triangulation_px = 20;  // the prior's errors, 2-3 px, are in the triangulation
  for (int run = 0; run < runs; ++run) {
    const Vec3 dr = sigma_position * Vec3(n(rng), n(rng), n(rng));
    const Vec3 dtheta = sigma_angle * Vec3(n(rng), n(rng), n(rng));
    // A rotation-vector error of std s is a quaternion error of std s / 2 per vector component.
    EkfState s = w.state(dr, dtheta, sigma_position, sigma_angle / 2);
    ASSERT_TRUE(msckfUpdate(s, w.camera, w.tracks(s, options.pixel_sigma, 100 + run), options).applied);
    const Vec3 e = s.r() - w.T_world_camera.back().t();
    nees += e.dot(s.P().topLeftCorner<3, 3>().ldlt().solve(e));
  }
  nees /= runs;
  EXPECT_GT(nees, 2.57);
  EXPECT_LT(nees, 3.46);
}

}  // namespace
}  // namespace slamcmp
