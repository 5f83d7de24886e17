#include "ekf/rolling_shutter.h"

#include <cmath>

#include <Eigen/LU>

#include "ekf/ekf_state.h"
#include "ekf/frame_measurement.h"
#include "ekf/motion_model.h"

namespace slamcmp {

namespace {

// Fixed-point steps on the point's row, from h's (its frame-time prediction): each predicts it from
// the camera when the last row was read (the motion model without impulses), at most `steps`,
// fewer once the row moves less than tolerance_px. h, *at_row and *F (if asked: d at_row / d
// x_camera) are the last step's; false where it cannot be predicted.
bool predictFromRowCamera(const CameraModel& camera, double readout, const CameraVector& x_camera,
                          const PredictFromPose& predict, int steps, double tolerance_px, PointMeasurement* h,
                          CameraVector* at_row, Mat13* F = nullptr) {
  double row = h->uv_distorted.y();
  for (int step = 0; step < steps; ++step) {
    *at_row = predictCamera(x_camera, camera.rowTime(readout, row), Eigen::Matrix<double, 6, 1>::Zero(), F);
    if (!predict(at_row->segment<3>(EkfState::kR), at_row->segment<4>(EkfState::kQ), h)) return false;
    const double moved = std::abs(h->uv_distorted.y() - row);
    row = h->uv_distorted.y();
    if (moved < tolerance_px) break;
  }
  return true;
}

}  // namespace

Vec2 rollingShutterShift(const CameraModel& camera, double readout, const Eigen::VectorXd& x,
                         const MapFeature& feature, const Vec2& uv_frame_time) {
  if (readout <= 0) return Vec2::Zero();
  PointMeasurement h;
  h.uv_distorted = uv_frame_time;
  CameraVector at_row;
  const PredictFromPose predict = [&](const Vec3& r, const Vec4& q, PointMeasurement* at) {
    return predictFeature(camera, r, q, x, feature, at);
  };
  if (!predictFromRowCamera(camera, readout, x.head<13>(), predict, 2, 0.0, &h, &at_row)) return Vec2::Zero();
  return h.uv_distorted - uv_frame_time;
}

Vec2 pixelAtFrameTime(const CameraModel& camera, double readout, const Vec3& w_camera, const Vec2& uv) {
  if (readout <= 0) return uv;
  // R_world_camera(t + tau) = R_world_camera(t) exp(w tau) (motion_model.h): a ray d seen at the
  // row's time is exp(w tau) d in the frame-time camera.
  const Vec2 xy = camera.undistortPixel(uv);
  const Vec3 ray = rotationFromRotvec(w_camera * camera.rowTime(readout, uv.y())) * Vec3(xy.x(), xy.y(), 1.0);
  if (ray.z() <= 0) return uv;
  return camera.project(ray);
}

double rollingShutterPixelSigma(const CameraModel& camera, double readout, const MotionModelOptions& motion) {
  const double q = motion.sigma_alpha * motion.sigma_alpha / motion.reference_rate;  // rad^2 / s^3
  const double half = 0.5 * readout;
  return 0.5 * (camera.fx + camera.fy) * std::sqrt(q * half * half * half / 3.0);
}

bool predictAtRowTime(const CameraModel& camera, double readout, const CameraVector& x_camera, const Vec3& p_world,
                      PointMeasurement* h, double min_depth) {
  return predictAtRowTime(
      camera, readout, x_camera,
      [&](const Vec3& r, const Vec4& q, PointMeasurement* at) { return predictMeasurement(camera, r, q, p_world, at, min_depth); },
      h);
}

bool predictAtRowTime(const CameraModel& camera, double readout, const CameraVector& x_camera,
                      const PredictFromPose& predict, PointMeasurement* h) {
  if (!predict(x_camera.segment<3>(EkfState::kR), x_camera.segment<4>(EkfState::kQ), h)) return false;
  h->row_timed = false;
  if (readout <= 0) return true;
  // Each step moves the row by about (d v / d tau) * readout / height times the last step's move
  // (0.03 for a feature moving 500 px/s under a 30 ms readout).
  constexpr int kMaxSteps = 8;
  constexpr double kRowTolerancePx = 1e-4;
  Mat13 F;
  CameraVector at_row;
  if (!predictFromRowCamera(camera, readout, x_camera, predict, kMaxSteps, kRowTolerancePx, h, &at_row, &F))
    return false;
  // h(x) = g(camera at tau(row), x) with row h's own second coordinate: dh = G dx + (dg/dtau) tau'
  // d row, so (I - (dg/dtau) tau' e_row^T) dh = G dx with G = [H_r H_q] d(r, q)_row / d x.
  Eigen::Matrix<double, 2, 7> H_pose;
  H_pose << h->H_r, h->H_q;
  const Eigen::Matrix<double, 2, 13> G = H_pose * F.topRows<7>();
  Eigen::Matrix<double, 7, 1> pose_rate;  // d (r, q) / d tau at the row: v and q * (0, w) / 2
  pose_rate << at_row.segment<3>(EkfState::kV),
      0.5 * quatMultiply(at_row.segment<4>(EkfState::kQ), Vec4(0, at_row(EkfState::kW), at_row(EkfState::kW + 1),
                                                                 at_row(EkfState::kW + 2)));
  const Vec2 g_tau = H_pose * pose_rate;
  Mat2 M = Mat2::Identity();
  M.col(1) -= g_tau * readout / (camera.height - 1.0);
  const Mat2 M_inv = M.inverse();
  const Eigen::Matrix<double, 2, 13> H = M_inv * G;
  h->H_r = H.middleCols<3>(EkfState::kR);
  h->H_q = H.middleCols<4>(EkfState::kQ);
  h->H_v = H.middleCols<3>(EkfState::kV);
  h->H_w = H.middleCols<3>(EkfState::kW);
  h->H_y = M_inv * h->H_y;
  h->row_timed = true;
  return true;
}

}  // namespace slamcmp
