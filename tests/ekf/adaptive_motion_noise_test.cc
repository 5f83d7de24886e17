// The motion noise estimated from the filter's velocity corrections (ekf/adaptive_motion_noise.h),
// on a simulation of the constant-velocity model with known impulses: a camera whose position
// and orientation are measured each frame (1 mm, 0.001 per quaternion component) by a filter
// that starts with ten times the true noise.
#include "ekf/adaptive_motion_noise.h"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "ekf/ekf_update.h"
#include "ekf/motion_model.h"

namespace slamcmp {
namespace {

constexpr double kDt = 0.1;  // 10 fps, the presets' rate

class Simulation {
 public:
  explicit Simulation(const MotionModelOptions& filter) : noise_(filter) {
    truth_ << 0, 0, -1, 1, 0, 0, 0, 0.1, 0, 0, 0, 0.2, 0;
    Mat13 P0 = Mat13::Zero();
    P0.diagonal() << Vec3::Constant(1e-6), Vec4::Constant(1e-6), Vec3::Constant(1e-2), Vec3::Constant(1e-2);
    state_.reset(SE3(), P0);
    state_.x().head<13>() = truth_;
  }

  // One frame of the truth with impulses of the given sigmas, then the filter's predict and update.
  void step(double sigma_a, double sigma_alpha) {
    MotionModelOptions truth;
    truth.sigma_a = sigma_a;
    truth.sigma_alpha = sigma_alpha;
    const Eigen::Matrix<double, 6, 6> Q = impulseCovariance(truth, kDt);
    Eigen::Matrix<double, 6, 1> n;
    for (int i = 0; i < 6; ++i) n(i) = std::sqrt(Q(i, i)) * normal_(rng_);
    truth_ = predictCamera(truth_, kDt, n);

    predict(state_, kDt, noise_.next(state_, kDt));
    constexpr int m = 7;  // r and q measured directly
    Eigen::Matrix<double, m, 1> sigma;
    sigma << Vec3::Constant(1e-3), Vec4::Constant(1e-3);
    Eigen::VectorXd nu(m);
    for (int i = 0; i < m; ++i) nu(i) = truth_(i) + sigma(i) * normal_(rng_) - state_.x()(i);
    Eigen::MatrixXd S = state_.P().topLeftCorner<m, m>();
    S.diagonal() += sigma.cwiseAbs2();
    ASSERT_TRUE(kalmanUpdate(state_, state_.P().leftCols<m>(), S, nu));
  }

  const MotionModelOptions& noise() const { return noise_.current(); }

 private:
  AdaptiveMotionNoise noise_;
  EkfState state_;
  CameraVector truth_;
  std::mt19937 rng_{7};
  std::normal_distribution<double> normal_;
};

MotionModelOptions adaptive() {
  MotionModelOptions o;
  o.sigma_a = 2.0;  // ten times the truth below: where it starts and the most it takes
  o.sigma_alpha = 3.0;
  o.adaptive.enabled = true;
  o.adaptive.min_sigma_a = 0.01;
  o.adaptive.min_sigma_alpha = 0.01;
  return o;
}

// Averaged over the last 10 s of 40 (from ten times the truth, 60 time constants before), the
// estimate is the truth's within 30 % (its own spread over a time constant of 5 frames is about
// 40 %, so the average is what is tested), and 1 s into a fivefold rise it is past half the new
// value.
TEST(AdaptiveMotionNoise, FindsTheTrueImpulsesFromTenTimesThemAndFollowsARise) {
  Simulation sim(adaptive());
  double sum_a = 0, sum_alpha = 0;
  for (int k = 0; k < 400; ++k) {
    sim.step(0.2, 0.3);
    if (k >= 300) sum_a += sim.noise().sigma_a / 100, sum_alpha += sim.noise().sigma_alpha / 100;
  }
  EXPECT_NEAR(sum_a, 0.2, 0.2 * 0.3);
  EXPECT_NEAR(sum_alpha, 0.3, 0.3 * 0.3);
  for (int k = 0; k < 10; ++k) sim.step(1.0, 1.5);
  EXPECT_GT(sim.noise().sigma_a, 0.5);
  EXPECT_GT(sim.noise().sigma_alpha, 0.75);
}

// One step of the covariance-matching rule written out here (Mohamed and Schwarz eq. 30, as the
// header states it): between two posteriors an interval dt apart, the per-axis impulse variance
// is (|v_k - v_k-1|^2 + tr P_vv,k - tr P_vv,k-1) / 3, as a sigma^2 at the reference rate
// (times reference_rate / dt), averaged into sigma_a^2 with weight 1 - exp(-dt / time_constant).
// The velocity covariance shrinks between the two (the filter grew surer: the sample is smaller
// than the correction alone) while the angular velocity's grows (larger). To 1e-12 relative (a
// few roundings); the trace differences move sigma_a by 1 % and sigma_alpha by 1 %, so a sign
// flipped on either is seen.
TEST(AdaptiveMotionNoise, OneStepIsTheCovarianceMatchingRule) {
  const MotionModelOptions o = adaptive();
  AdaptiveMotionNoise noise(o);
  const double dt = 0.1;
  const Vec3 v0(0.2, 0.0, -0.1), w0(0.0, 0.3, 0.1), v1(0.3, 0.0, -0.1), w1(0.0, 0.5, 0.1);
  Mat3 P_vv0, P_vv1, P_ww0, P_ww1;
  P_vv0 << 1.2e-3, 2e-4, 0, 2e-4, 9e-4, -1e-4, 0, -1e-4, 9e-4;  // trace 3e-3
  P_vv1 = P_vv0 / 3;                                             // trace 1e-3
  P_ww0 = Mat3::Identity() * 1e-3 / 3;                           // trace 1e-3
  P_ww1 = P_ww0 * 6;                                             // trace 6e-3
  EkfState posterior0, posterior1;
  Mat13 P = Mat13::Identity() * 1e-4;
  P.block<3, 3>(EkfState::kV, EkfState::kV) = P_vv0;
  P.block<3, 3>(EkfState::kW, EkfState::kW) = P_ww0;
  posterior0.reset(SE3(), P);
  posterior0.x().segment<3>(EkfState::kV) = v0;
  posterior0.x().segment<3>(EkfState::kW) = w0;
  P.block<3, 3>(EkfState::kV, EkfState::kV) = P_vv1;
  P.block<3, 3>(EkfState::kW, EkfState::kW) = P_ww1;
  posterior1.reset(SE3(), P);
  posterior1.x().segment<3>(EkfState::kV) = v1;
  posterior1.x().segment<3>(EkfState::kW) = w1;

  EXPECT_EQ(noise.next(posterior0, dt).sigma_a, o.sigma_a);  // nothing to compare with yet
  const MotionModelOptions& next = noise.next(posterior1, 0.05);  // the interval ended at posterior1 is dt

  const double to_sigma2 = o.reference_rate / dt / 3;
  const double a2 = ((v1 - v0).squaredNorm() + P_vv1.trace() - P_vv0.trace()) * to_sigma2;
  const double alpha2 = ((w1 - w0).squaredNorm() + P_ww1.trace() - P_ww0.trace()) * to_sigma2;
  const double weight = 1 - std::exp(-dt / o.adaptive.time_constant);
  const double sigma_a2 = o.sigma_a * o.sigma_a + weight * (a2 - o.sigma_a * o.sigma_a);
  const double sigma_alpha2 = o.sigma_alpha * o.sigma_alpha + weight * (alpha2 - o.sigma_alpha * o.sigma_alpha);
  ASSERT_NEAR(a2, 0.8, 1e-12);      // between the floor and the set noise: no clamping
  ASSERT_NEAR(alpha2, 4.5, 1e-12);
  EXPECT_NEAR(next.sigma_a, std::sqrt(sigma_a2), 1e-12 * std::sqrt(sigma_a2));
  EXPECT_NEAR(next.sigma_alpha, std::sqrt(sigma_alpha2), 1e-12 * std::sqrt(sigma_alpha2));
}

TEST(AdaptiveMotionNoise, StaysBetweenItsFloorAndTheSetNoise) {
  MotionModelOptions o = adaptive();
  o.adaptive.min_sigma_a = 0.5;
  o.adaptive.min_sigma_alpha = 0.5;
  Simulation still(o);
  for (int k = 0; k < 200; ++k) still.step(1e-6, 1e-6);
  EXPECT_DOUBLE_EQ(still.noise().sigma_a, 0.5);
  EXPECT_DOUBLE_EQ(still.noise().sigma_alpha, 0.5);
  Simulation shaken(o);
  for (int k = 0; k < 200; ++k) shaken.step(20, 30);
  EXPECT_DOUBLE_EQ(shaken.noise().sigma_a, 2.0);
  EXPECT_DOUBLE_EQ(shaken.noise().sigma_alpha, 3.0);
}

TEST(AdaptiveMotionNoise, OffLeavesTheSetNoise) {
  MotionModelOptions o = adaptive();
  o.adaptive.enabled = false;
  Simulation sim(o);
  for (int k = 0; k < 100; ++k) sim.step(0.2, 0.3);
  EXPECT_EQ(sim.noise().sigma_a, 2.0);
  EXPECT_EQ(sim.noise().sigma_alpha, 3.0);
}

// A restart (the filter reset, or the board found where it was not expected) is back to the set
// noise.
TEST(AdaptiveMotionNoise, ARestartGoesBackToTheSetNoise) {
  const MotionModelOptions o = adaptive();
  AdaptiveMotionNoise noise(o);
  EkfState state;
  Mat13 P = Mat13::Identity() * 1e-4;
  state.reset(SE3(), P);
  for (int k = 0; k < 60; ++k) noise.next(state, kDt);  // no corrections: down to the floor in 6 s
  EXPECT_DOUBLE_EQ(noise.current().sigma_a, o.adaptive.min_sigma_a);
  noise.restart();
  EXPECT_EQ(noise.current().sigma_a, 2.0);
  EXPECT_EQ(noise.current().sigma_alpha, 3.0);
}

TEST(AdaptiveMotionNoise, OptionsRefuseFloorsAboveTheSetNoiseAndNoTimeConstant) {
  MotionModelOptions o = adaptive();
  EXPECT_NO_THROW(o.check());
  o.adaptive.min_sigma_a = 2.5;  // above sigma_a
  EXPECT_THROW(o.check(), OptionError);
  o.adaptive.enabled = false;  // not used, not refused
  EXPECT_NO_THROW(o.check());
  MotionModelOptions alpha = adaptive();
  alpha.adaptive.min_sigma_alpha = 4;
  EXPECT_THROW(alpha.check(), OptionError);
  AdaptiveMotionOptions a;
  a.time_constant = 0;
  EXPECT_THROW(a.check(), OptionError);
  a.time_constant = NAN;
  EXPECT_THROW(a.check(), OptionError);
}

}  // namespace
}  // namespace slamcmp
