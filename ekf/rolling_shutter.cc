#include "ekf/rolling_shutter.h"

#include "ekf/ekf_state.h"
#include "ekf/frame_measurement.h"
#include "ekf/motion_model.h"

namespace slamcmp {

Vec2 rollingShutterShift(const CameraModel& camera, double readout, const Eigen::VectorXd& x,
                         const MapFeature& feature, const Vec2& uv_frame_time) {
  if (readout <= 0) return Vec2::Zero();
  const CameraVector camera_now = x.head<13>();
  Vec2 uv = uv_frame_time;
  for (int step = 0; step < 2; ++step) {
    // The camera when the row is read, by the motion model without impulses.
    const CameraVector at_row =
        predictCamera(camera_now, camera.rowTime(readout, uv.y()), Eigen::Matrix<double, 6, 1>::Zero());
    PointMeasurement h;
    if (!predictFeature(camera, at_row.segment<3>(EkfState::kR), at_row.segment<4>(EkfState::kQ), x, feature, &h))
      return Vec2::Zero();
    uv = h.uv_distorted;
  }
  return uv - uv_frame_time;
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

}  // namespace slamcmp
