#include "ekf/relocaliser.h"

#include <cmath>
#include <limits>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

namespace slamcmp {

namespace {

constexpr int kOrbPatch = 31;  // ORB's patch side and the border it keeps (OpenCV's defaults)

// ORB's orientation (Rublee et al. 2011, eq. 2-3): the angle of the intensity centroid of the
// disc of radius 15 around the corner, in degrees as cv::KeyPoint holds it.
float centroidAngleDeg(const cv::Mat& grey, const cv::Point2f& uv) {
  const int r = kOrbPatch / 2;
  const int cx = cvRound(uv.x), cy = cvRound(uv.y);
  double m10 = 0, m01 = 0;
  for (int dy = -r; dy <= r; ++dy)
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy > r * r) continue;
      const double v = grey.at<uchar>(cy + dy, cx + dx);
      m10 += dx * v;
      m01 += dy * v;
    }
  double angle = std::atan2(m01, m10) * 180.0 / M_PI;
  if (angle < 0) angle += 360;
  return static_cast<float>(angle);
}

}  // namespace

Relocaliser::Relocaliser(const RelocalisationOptions& options) : options_(options), orb_(cv::ORB::create()) {}

cv::Mat Relocaliser::describeAll(const cv::Mat& grey, std::vector<cv::Point2f>* uv_distorted) const {
  // ORB drops keypoints within its patch of the border; the disc above must fit too.
  const float border = kOrbPatch + 1;
  std::vector<cv::KeyPoint> keypoints;
  std::vector<cv::Point2f> kept;
  for (const cv::Point2f& p : *uv_distorted) {
    if (!(p.x >= border && p.y >= border && p.x < grey.cols - border && p.y < grey.rows - border)) continue;
    keypoints.emplace_back(p, static_cast<float>(kOrbPatch), centroidAngleDeg(grey, p));
    kept.push_back(p);
  }
  cv::Mat descriptors;
  if (!keypoints.empty()) orb_->compute(grey, keypoints, descriptors);
  if (keypoints.size() != kept.size()) return {};  // ORB kept every one inside its border before
  uv_distorted->swap(kept);
  return descriptors;
}

cv::Mat Relocaliser::describe(const cv::Mat& grey, const Vec2& uv) const {
  if (!(uv.x() >= 0 && uv.y() >= 0 && uv.x() < grey.cols && uv.y() < grey.rows)) return {};
  // ORB over the corner's neighbourhood alone gives the bits it gives over the whole image (its
  // steered pattern and blur reach 22 pixels, its border test 32), where ORB pads and blurs all it
  // is given: 0.02 against 0.18 ms a corner at 640x480. The crop moves the corner by a whole even
  // number of pixels, so ORB's rounding (half to even) rounds it alike.
  constexpr int kMargin = 48;
  static_assert(kMargin % 2 == 0 && kMargin > kOrbPatch + 1, "an even margin beyond ORB's border");
  const cv::Point2f p(static_cast<float>(uv.x()), static_cast<float>(uv.y()));  // as ORB's keypoint holds it
  const int cx = cvRound(p.x), cy = cvRound(p.y);
  const cv::Rect around = cv::Rect(cx - kMargin, cy - kMargin, 2 * kMargin + 1, 2 * kMargin + 1) &
                          cv::Rect(0, 0, grey.cols, grey.rows);
  std::vector<cv::Point2f> one = {p - cv::Point2f(around.tl())};
  const cv::Mat descriptor = describeAll(grey(around).clone(), &one);  // a copy: ORB's padding reads no pixel beyond it
  return one.size() == 1 ? descriptor : cv::Mat();
}

std::vector<cv::DMatch> Relocaliser::matchAll(const cv::Mat& descriptors, const cv::Mat& frame_descriptors) const {
  std::vector<std::vector<cv::DMatch>> knn;
  cv::BFMatcher(cv::NORM_HAMMING).knnMatch(descriptors, frame_descriptors, knn, 2);
  std::vector<cv::DMatch> matches;
  for (const std::vector<cv::DMatch>& m : knn)
    if (m.size() == 2 && m[0].distance < options_.ratio * m[1].distance) matches.push_back(m[0]);
  return matches;
}

std::vector<cv::DMatch> Relocaliser::matchNear(const cv::Mat& descriptors, const cv::Mat& frame_descriptors,
                                               const std::vector<cv::Point2f>& uv_distorted, const CameraModel& camera,
                                               const std::vector<Vec3>& p_world, const SE3& T_world_camera) const {
  const SE3 T_camera_world = T_world_camera.inverse();
  const double r2 = options_.guided_radius_px * options_.guided_radius_px;
  std::vector<cv::DMatch> matches;
  for (int i = 0; i < descriptors.rows; ++i) {
    const Vec3 p_camera = T_camera_world * p_world[i];
    if (!(p_camera.z() > 0)) continue;
    const Vec2 uv = camera.project(p_camera);
    if (!camera.inImage(uv, -options_.guided_radius_px)) continue;
    double best = std::numeric_limits<double>::infinity(), second = best;
    int best_j = -1;
    for (int j = 0; j < frame_descriptors.rows; ++j) {
      const double du = uv_distorted[j].x - uv.x(), dv = uv_distorted[j].y - uv.y();
      if (du * du + dv * dv > r2) continue;
      const double d = cv::norm(descriptors.row(i), frame_descriptors.row(j), cv::NORM_HAMMING);
      if (d < best) {
        second = best, best = d, best_j = j;
      } else if (d < second) {
        second = d;
      }
    }
    if (best_j >= 0 && best <= options_.guided_max_hamming && best < options_.ratio * second)
      matches.emplace_back(i, best_j, static_cast<float>(best));
  }
  return matches;
}

std::optional<SE3> Relocaliser::relocalise(const cv::Mat& grey, const CameraModel& camera,
                                           const std::vector<Vec3>& p_world,
                                           const std::vector<Mat3>& P_points, const cv::Mat& descriptors,
                                           int* inliers, const SE3* T_world_camera_guess) const {
  *inliers = 0;
  if (static_cast<int>(p_world.size()) < options_.min_inliers || P_points.size() != p_world.size() ||
      descriptors.rows != static_cast<int>(p_world.size()))
    return std::nullopt;
  std::vector<cv::Point2f> uv_distorted;
  cv::goodFeaturesToTrack(grey, uv_distorted, options_.frame_corners, 0.001, 5);
  const cv::Mat frame_descriptors = describeAll(grey, &uv_distorted);
  if (frame_descriptors.rows < 2) return std::nullopt;
  const std::optional<SE3> found =
      poseFromMatches(matchAll(descriptors, frame_descriptors), uv_distorted, camera, p_world, P_points, inliers);
  if (found || !T_world_camera_guess || !(options_.guided_radius_px > 0)) return found;
  return poseFromMatches(
      matchNear(descriptors, frame_descriptors, uv_distorted, camera, p_world, *T_world_camera_guess), uv_distorted,
      camera, p_world, P_points, inliers);
}

std::optional<SE3> Relocaliser::poseFromMatches(const std::vector<cv::DMatch>& matches,
                                                const std::vector<cv::Point2f>& uv_distorted,
                                                const CameraModel& camera, const std::vector<Vec3>& p_world,
                                                const std::vector<Mat3>& P_points, int* inliers) const {
  std::vector<cv::Point3d> p_world_matched;
  std::vector<cv::Point2d> xy_normalised;  // the lens's distortion removed
  std::vector<int> point_index;            // of each match, into p_world
  for (const cv::DMatch& m : matches) {
    const Vec3& p = p_world[m.queryIdx];
    const cv::Point2f& uv = uv_distorted[m.trainIdx];
    const Vec2 xy = camera.undistortPixel(Vec2(uv.x, uv.y));
    p_world_matched.emplace_back(p.x(), p.y(), p.z());
    xy_normalised.emplace_back(xy.x(), xy.y());
    point_index.push_back(m.queryIdx);
  }
  if (static_cast<int>(p_world_matched.size()) < options_.min_inliers) return std::nullopt;
  cv::Mat rvec, tvec;
  std::vector<int> kept;
  const double focal = 0.5 * (camera.fx + camera.fy);
  if (!cv::solvePnPRansac(p_world_matched, xy_normalised, cv::Matx33d::eye(), cv::noArray(), rvec, tvec, false, 300,
                          static_cast<float>(options_.max_error_px / focal), 0.999, kept) ||
      static_cast<int>(kept.size()) < options_.min_inliers ||
      static_cast<double>(kept.size()) < options_.min_inlier_ratio * static_cast<double>(p_world_matched.size()))
    return std::nullopt;
  Vec3 rotvec, t;
  cv::cv2eigen(rvec, rotvec);
  cv::cv2eigen(tvec, t);
  if (!rotvec.allFinite() || !t.allFinite()) return std::nullopt;
  const SE3 T_camera_world = SE3::fromRotvec(rotvec, t);
  int confirmed = 0;  // inliers whose point is known to within the inlier test where it projects
  for (int k : kept) {
    const Vec3 p_camera = T_camera_world * p_world[point_index[k]];
    // The points in front of the camera: a projection cannot tell a point behind the camera from
    // its mirror image (tum_fr1_rpy: 6 of 10 matches fitted a pose that put them all behind).
    if (!(p_camera.z() > 0)) return std::nullopt;
    // In the inlier test's own measure: normalised coordinates times the focal length.
    const Mat23 J_uv_world = focal * pinholeJacobian(p_camera) * T_camera_world.R();
    const Mat2 P_uv = J_uv_world * P_points[point_index[k]] * J_uv_world.transpose();
    if (largestStd(P_uv) <= options_.max_error_px) ++confirmed;
  }
  if (confirmed < options_.min_inliers) return std::nullopt;
  *inliers = confirmed;
  return T_camera_world.inverse();
}

}  // namespace slamcmp
