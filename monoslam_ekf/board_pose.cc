#include "monoslam_ekf/board_pose.h"

#include <opencv2/calib3d.hpp>

namespace slamcmp {

SE3 boardPose(const CameraModel& camera, const ChessboardTarget& target,
              const std::vector<cv::Point2f>& uv_distorted) {
  std::vector<cv::Point3f> p_world;
  for (const Vec3& p : target.cornersWorld())
    p_world.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
  cv::Mat rvec, tvec;
  cv::solvePnP(p_world, uv_distorted, camera.cameraMatrix(), camera.distortionVector(), rvec, tvec);
  const Vec3 rotvec(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2));
  const Vec3 t(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
  return SE3::fromRotvec(rotvec, t).inverse();  // solvePnP gives T_camera_world
}

std::vector<Vec2> outerCornerPixels(const ChessboardTarget& target,
                                    const std::vector<cv::Point2f>& uv_distorted) {
  const int c = target.cols, r = target.rows;
  const int index[4] = {0, c - 1, (r - 1) * c + c - 1, (r - 1) * c};
  std::vector<Vec2> out;
  for (int i : index) out.emplace_back(uv_distorted[i].x, uv_distorted[i].y);
  return out;
}

}  // namespace slamcmp
