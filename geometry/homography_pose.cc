#include "geometry/homography_pose.h"

#include <cmath>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include "geometry/hartley_normalisation.h"

namespace slamcmp {

namespace {

// d x (H s) = 0 for Hartley-normalised s and d: two independent rows of the DLT in h = vec(H) by
// rows.
Eigen::Matrix<double, 2, 9> dltRows(const Vec3& s, const Vec3& d) {
  Eigen::Matrix<double, 2, 9> rows;
  rows << 0, 0, 0, -d.z() * s.transpose(), d.y() * s.transpose(), d.z() * s.transpose(), 0, 0, 0,
      -d.x() * s.transpose();
  return rows;
}

}  // namespace

Mat3 homographyDlt(const std::vector<Vec2>& src, const std::vector<Vec2>& dst) {
  const int n = static_cast<int>(src.size());
  const Mat3 Ts = hartleyNormalisation(src), Td = hartleyNormalisation(dst);
  Eigen::MatrixXd A(2 * n, 9);
  for (int i = 0; i < n; ++i) {
    const Vec3 s = Ts * src[i].homogeneous();
    const Vec3 d = Td * dst[i].homogeneous();
    A.middleRows<2>(2 * i) = dltRows(s, d);
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(A, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Mat3 Hn;
  Hn << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  Mat3 H = Td.inverse() * Hn * Ts;
  // The SVD's sign is arbitrary; the points seen are all on one side of the plane's horizon.
  if ((H * src.front().homogeneous()).z() < 0) H = -H;
  return H / H.norm();
}

bool determinesAHomography(const std::vector<Vec2>& points) {
  if (points.size() < 4) return false;
  for (const Vec2& p : points)
    if (!p.allFinite()) return false;
  const Mat3 T = hartleyNormalisation(points);
  // A^T A of the DLT rows for H = I (d = s): its eigenvalues are A's singular values squared.
  Eigen::Matrix<double, 9, 9> AtA = Eigen::Matrix<double, 9, 9>::Zero();
  for (const Vec2& p : points) {
    const Vec3 s = T * p.homogeneous();
    const Eigen::Matrix<double, 2, 9> rows = dltRows(s, s);
    AtA += rows.transpose() * rows;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 9, 9>> eigen(AtA, Eigen::EigenvaluesOnly);
  return eigen.eigenvalues()(1) > 1e-12 * eigen.eigenvalues()(8);  // (1e-6)^2
}

std::vector<double> homographyErrors(const Mat3& H, const std::vector<Vec2>& src, const std::vector<Vec2>& dst) {
  std::vector<double> e(src.size());
  for (size_t i = 0; i < src.size(); ++i) e[i] = ((H * src[i].homogeneous()).hnormalized() - dst[i]).norm();
  return e;
}

SE3 poseFromHomography(const Mat3& H, const Mat3& K) {
  const Mat3 Kinv = K.inverse();
  const Vec3 k1 = Kinv * H.col(0), k2 = Kinv * H.col(1), k3 = Kinv * H.col(2);
  double lambda = 1.0 / k1.norm();  // thesis eq. 3.11
  if (lambda * k3.z() < 0) lambda = -lambda;  // the board is in front of the camera
  const Vec3 r1 = lambda * k1;                // eq. 3.12
  const Vec3 r2 = lambda * k2;                // eq. 3.13
  const Vec3 r3 = r1.cross(r2);               // eq. 3.14
  const Vec3 t = lambda * k3;                 // eq. 3.15
  Mat3 Q;
  Q << r1, r2, r3;
  return SE3(nearestRotation(Q), t);          // eqs. 3.16, 3.17
}

BoardPose boardPose(const std::vector<Vec3>& p_board, const std::vector<Vec2>& xy_normalised,
                    double focal_px, const BoardPoseOptions& options) {
  std::vector<Vec2> plane(p_board.size());
  for (size_t i = 0; i < p_board.size(); ++i) plane[i] = p_board[i].head<2>();
  BoardPose pose;
  pose.T_camera_board = poseFromHomography(homographyDlt(plane, xy_normalised), Mat3::Identity());
  if (options.refine) {
    const PoseRefinementResult r =
        refinePose(pose.T_camera_board, p_board, xy_normalised, focal_px, options.refinement);
    pose.T_camera_board = r.T_camera_world;
    pose.rms_px = r.rms_px;
  } else {
    double sum = 0;
    for (double e : reprojectionErrorsPx(pose.T_camera_board, p_board, xy_normalised, focal_px)) sum += e * e;
    pose.rms_px = std::sqrt(sum / static_cast<double>(p_board.size()));
  }
  return pose;
}

BoardPose wholeBoardPose(const CameraModel& camera, const ChessboardTarget& target,
                         const std::vector<cv::Point2f>& uv_distorted, const BoardPoseOptions& options) {
  std::vector<Vec2> xy;
  xy.reserve(uv_distorted.size());
  for (const cv::Point2f& p : uv_distorted) xy.push_back(camera.undistortPixel(Vec2(p.x, p.y)));
  return boardPose(target.cornersWorld(), xy, 0.5 * (camera.fx + camera.fy), options);
}

}  // namespace slamcmp
