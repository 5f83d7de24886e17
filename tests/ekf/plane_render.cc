#include "tests/ekf/plane_render.h"

#include <cmath>

namespace slamcmp::test {

double planeTexture(double X, double Y) {
  const double v = 128 + 45 * std::sin(37 * X + 5 * Y) * std::cos(29 * Y - 3 * X) + 35 * std::sin(61 * X + 43 * Y) +
                   25 * std::cos(83 * Y - 17 * X * X);
  return std::min(255.0, std::max(0.0, v));
}

cv::Mat renderPlane(const CameraModel& camera, const SE3& T_world_camera, double plane_z) {
  cv::Mat image(camera.height, camera.width, CV_8U, cv::Scalar(0));
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Vec2 xy = camera.undistortPixel(Vec2(u, v));
      const Vec3 dir = T_world_camera.R() * Vec3(xy.x(), xy.y(), 1.0);
      if (std::abs(dir.z()) < 1e-9) continue;
      const double s = (plane_z - T_world_camera.t().z()) / dir.z();
      if (s <= 0) continue;
      const Vec3 p = T_world_camera.t() + s * dir;
      image.at<uchar>(v, u) = static_cast<uchar>(std::lround(planeTexture(p.x(), p.y())));
    }
  }
  return image;
}

CameraModel testCamera() {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = 520;
  c.fy = 515;
  c.cx = 318.5;
  c.cy = 242.0;
  c.num_distortion = 5;
  c.distortion = {-0.12, 0.03, 0.0004, -0.0003, 0.0, 0, 0, 0};
  return c;
}

const SE3 kT_world_camera0(Mat3::Identity(), Vec3(0, 0, -1.6));
const SE3 kT_world_camera1(Mat3::Identity(), Vec3(0.15, 0, -1.6));

const cv::Mat& planeView0() {
  static const cv::Mat grey = renderPlane(testCamera(), kT_world_camera0, 0.0);
  return grey;
}

const cv::Mat& planeView1() {
  static const cv::Mat grey = renderPlane(testCamera(), kT_world_camera1, 0.0);
  return grey;
}

}  // namespace slamcmp::test
