#include "monoslam_ekf/ekf_update.h"

#include <gtest/gtest.h>

#include "tests/monoslam_ekf/plane_render.h"

namespace slamcmp {
namespace {

EkfState uncertainState() {
  EkfState s;
  Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Identity() * 1e-4;
  s.reset(SE3::fromRotvec(Vec3(0.05, -0.1, 0.02), Vec3(0.1, 0.1, -1.0)), P);
  s.append(Vec3(0.2, 0.1, 0.0), Mat3::Identity() * 1e-3, Eigen::MatrixXd::Zero(3, 13));
  s.append(Vec3(-0.1, 0.3, 0.1), Mat3::Identity() * 2e-3, Eigen::MatrixXd::Zero(3, 16));
  return s;
}

PointObservation observe(const EkfState& s, const CameraModel& camera, int offset, const Vec2& offset_px) {
  PointObservation o;
  o.offset = offset;
  predictMeasurement(camera, s.r(), s.q(), s.x().segment<3>(offset), &o.h);
  o.z = o.h.uv_distorted + offset_px;
  return o;
}

// With the Jacobians held fixed, one batch update equals two sequential updates, the second
// innovation taken against the first update's linearised prediction.
TEST(EkfUpdate, BatchEqualsSequentialForAFixedLinearisation) {
  const CameraModel camera = test::testCamera();
  const EkfState prior = uncertainState();
  const PointObservation a = observe(prior, camera, 13, Vec2(2.0, -1.0));
  const PointObservation b = observe(prior, camera, 16, Vec2(-1.5, 0.5));

  EkfState batch = prior;
  batchUpdate(batch, {a, b}, 1.0);

  EkfState sequential = prior;
  batchUpdate(sequential, {a}, 1.0);
  PointObservation b2 = b;
  // Linearised prediction of b at the updated state (q renormalisation is second order here).
  const Eigen::VectorXd dx = sequential.x() - prior.x();
  b2.h.uv_distorted += b.h.H_r * dx.segment<3>(EkfState::kR) + b.h.H_q * dx.segment<4>(EkfState::kQ) +
                       b.h.H_y * dx.segment<3>(16);
  batchUpdate(sequential, {b2}, 1.0);
  EXPECT_LT((batch.x() - sequential.x()).norm(), 1e-6);
  EXPECT_LT((batch.P() - sequential.P()).norm(), 1e-7);
}

TEST(EkfUpdate, UpdateShrinksUncertaintyAndKeepsSymmetry) {
  const CameraModel camera = test::testCamera();
  EkfState s = uncertainState();
  const Eigen::MatrixXd S = innovationCovariance(s, {observe(s, camera, 13, Vec2::Zero())}, 1.0);
  const double trace_before = s.P().trace();
  batchUpdate(s, {observe(s, camera, 13, Vec2(1, 1)), observe(s, camera, 16, Vec2(0, 0))}, 1.0);
  EXPECT_LT(s.P().trace(), trace_before);
  EXPECT_LT((s.P() - s.P().transpose()).norm(), 1e-15);
  EXPECT_NEAR(s.q().norm(), 1.0, 1e-15);
  EXPECT_GT(S(0, 0), 1.0);  // pixel noise plus the state's share
}

}  // namespace
}  // namespace slamcmp
