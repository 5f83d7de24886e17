#include "geometry/homography_pose.h"

#include <fstream>
#include <random>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "core/camera.h"
#include "core/target.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

// A camera looking at the 9x6 board (4 cm squares) from a varied pose.
SE3 boardInCamera(int k) {
  const Vec3 rotvec(0.3 * std::sin(k * 1.3), 0.4 * std::cos(k * 0.7), 0.8 * std::sin(k * 2.1));
  const Vec3 t(-0.16 + 0.05 * std::sin(k), -0.1 + 0.04 * std::cos(2 * k), 0.5 + 0.3 * (k % 4));
  return SE3::fromRotvec(rotvec, t);
}

std::vector<Vec2> projectNormalised(const SE3& T_camera_board, const std::vector<Vec3>& p_board) {
  std::vector<Vec2> xy;
  for (const auto& p : p_board) xy.push_back((T_camera_board * p).hnormalized());
  return xy;
}

double angleDeg(const Mat3& A, const Mat3& B) { return rotationAngle(A.transpose() * B) * 180 / M_PI; }

class HomographyPoseExact : public ::testing::TestWithParam<int> {};

TEST_P(HomographyPoseExact, RecoversThePoseToMachinePrecision) {
  ChessboardTarget board{9, 6, 0.04};
  const SE3 truth = boardInCamera(GetParam());
  const auto xy = projectNormalised(truth, board.cornersWorld());
  BoardPoseOptions no_refine;
  no_refine.refine = false;
  for (const BoardPoseOptions& options : {no_refine, BoardPoseOptions{}}) {
    const BoardPose pose = boardPose(board.cornersWorld(), xy, 500, options);
    EXPECT_LT(angleDeg(pose.T_camera_board.R(), truth.R()), 1e-9 * 180 / M_PI);
    EXPECT_LT((pose.T_camera_board.t() - truth.t()).norm(), 1e-9);
    EXPECT_LT(pose.rms_px, 1e-7);
  }
}

INSTANTIATE_TEST_SUITE_P(Poses, HomographyPoseExact, ::testing::Range(0, 8));

// The DLT's sign is fixed: every board point in front of the camera maps to a positive third
// coordinate (callers test the plane's horizon with it), and the homography is the true one up to
// that positive scale, whatever the pose (rolled past 90 degrees among them).
TEST(HomographyDlt, SignPutsTheSeenPointsInFront) {
  ChessboardTarget board{9, 6, 0.04};
  std::vector<Vec2> plane;
  for (const Vec3& p : board.cornersWorld()) plane.push_back(p.head<2>());
  for (int k = 0; k < 16; ++k) {
    const SE3 T_camera_board = boardInCamera(k) * SE3::fromRotvec(Vec3(0, 0, 0.4 * k), Vec3::Zero());
    const Mat3 H = homographyDlt(plane, projectNormalised(T_camera_board, board.cornersWorld()));
    Mat3 truth;
    truth << T_camera_board.R().col(0), T_camera_board.R().col(1), T_camera_board.t();
    EXPECT_LT((H - truth / truth.norm()).norm(), 1e-9) << "pose " << k;
    for (const Vec2& p : plane) EXPECT_GT((H * p.homogeneous()).z(), 0) << "pose " << k;
  }
}

// Hartley's point: with noisy correspondences the normalised DLT gives the same homography
// wherever the coordinates' origin and scale are, at both ends. The board in squares seen in pixels
// (f = 500, centre (320, 240), 0.5 px noise), and in metres about another origin seen in normalised
// coordinates: H_pixels is K H_normalised A up to scale (A: squares to metres), to 1e-9. Left out at
// either end, the normalisation moves it by about 1e-5.
TEST(HomographyDlt, SameHomographyWhereverTheCoordinatesAre) {
  ChessboardTarget board{9, 6, 0.04};
  Mat3 K, A;
  K << 500, 0, 320, 0, 500, 240, 0, 0, 1;
  A << 0.04, 0, -0.3, 0, 0.04, 0.7, 0, 0, 1;
  std::vector<Vec2> squares, metres;
  for (const Vec3& p : board.cornersWorld()) {
    squares.push_back(p.head<2>() / 0.04);
    metres.push_back((A * squares.back().homogeneous()).hnormalized());
  }
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0, 0.5);
  for (int k = 0; k < 8; ++k) {
    std::vector<Vec2> uv, xy;
    for (const Vec2& p : projectNormalised(boardInCamera(k), board.cornersWorld())) {
      uv.push_back((K * p.homogeneous()).hnormalized() + Vec2(noise(rng), noise(rng)));
      xy.push_back((K.inverse() * uv.back().homogeneous()).hnormalized());
    }
    const Mat3 H_pixels = homographyDlt(squares, uv);
    const Mat3 H_mapped = K * homographyDlt(metres, xy) * A;
    EXPECT_LT((H_pixels - H_mapped / H_mapped.norm()).norm(), 1e-9) << "pose " << k;
  }
}

// A partial board's corners on one row, column or diagonal of the grid, or a row with one corner
// off it, determine no homography (the DLT keeps a second null direction: a pose up to 180 degrees
// off); two rows, a row with two corners off it, or four in general position do. And where they
// do, the homography through them is the exact one.
TEST(HomographyDlt, OneLineOfCornersDoesNotDetermineTheHomography) {
  const auto grid = [](std::initializer_list<std::pair<int, int>> ij) {
    std::vector<Vec2> points;
    for (const auto& [i, j] : ij) points.emplace_back(0.04 * i, 0.04 * j);
    return points;
  };
  std::vector<Vec2> row, column, diagonal, two_rows;
  for (int k = 0; k < 9; ++k) {
    row.emplace_back(0.04 * k, 0.08);
    column.emplace_back(0.12, 0.04 * k);
    diagonal.emplace_back(0.04 * k, 0.04 * k);
    two_rows.emplace_back(0.04 * k, 0.04 * (k % 2));
  }
  EXPECT_FALSE(determinesAHomography(row));
  EXPECT_FALSE(determinesAHomography(column));
  EXPECT_FALSE(determinesAHomography(diagonal));
  EXPECT_FALSE(determinesAHomography(grid({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {6, 0}, {7, 0}, {3, 1}})));
  EXPECT_FALSE(determinesAHomography(grid({{0, 0}, {1, 0}, {0, 1}})));
  EXPECT_TRUE(determinesAHomography(two_rows));
  EXPECT_TRUE(determinesAHomography(grid({{0, 0}, {1, 0}, {2, 0}, {3, 0}, {4, 0}, {5, 0}, {6, 0}, {7, 0}, {3, 1}, {5, 1}})));
  EXPECT_TRUE(determinesAHomography(grid({{0, 0}, {1, 0}, {0, 1}, {1, 1}})));
  // Where it is determined, the DLT through the points recovers a homography exactly.
  Mat3 H;
  H << 1.1, 0.2, 0.3, -0.1, 0.9, 0.2, 0.05, 0.02, 1.0;
  const std::vector<Vec2> src = grid({{0, 0}, {1, 0}, {0, 1}, {1, 1}});
  std::vector<Vec2> dst;
  for (const Vec2& p : src) dst.push_back((H * p.homogeneous()).hnormalized());
  EXPECT_LT((homographyDlt(src, dst) - H / H.norm()).norm(), 1e-9);
}

// With 0.3 px corner noise: the refined pose and OpenCV's iterative PnP minimise the same
// reprojection error, so they agree to 1e-6 m and 1e-4 degree. Against the truth: the board spans
// 130 to 330 px (0.5 to 1.3 m), so 0.3 px noise leaves a few millimetres and, the tilt of a small
// board being weakly observed, up to about a degree (tolerance 1.5 degree, 5 mm; linear 10 mm).
TEST(HomographyPose, NoisyCornersAgreeWithSolvePnP) {
  ChessboardTarget board{9, 6, 0.04};
  CameraModel cam;
  cam.width = 640, cam.height = 480, cam.fx = cam.fy = 520, cam.cx = 320, cam.cy = 240;
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 0.3);
  std::vector<cv::Point3f> object;
  for (const auto& p : board.cornersWorld()) object.emplace_back(p.x(), p.y(), 0);
  for (int k = 0; k < 8; ++k) {
    const SE3 truth = boardInCamera(k);
    std::vector<Vec2> xy;
    std::vector<cv::Point2f> uv;
    for (const auto& p : board.cornersWorld()) {
      const Vec2 px = cam.project(truth * p) + Vec2(noise(rng), noise(rng));
      uv.emplace_back(px.x(), px.y());
      xy.push_back(cam.normalisedFromPixel(px));
    }
    const BoardPose pose = boardPose(board.cornersWorld(), xy, cam.fx, {});
    cv::Mat rvec, tvec;
    ASSERT_TRUE(cv::solvePnP(object, uv, cam.cameraMatrix(), cv::Mat(), rvec, tvec, false, cv::SOLVEPNP_ITERATIVE));
    const Vec3 t_cv(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    const Mat3 R_cv = rotationFromRotvec(Vec3(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)));
    EXPECT_LT((pose.T_camera_board.t() - t_cv).norm(), 1e-6) << k;
    EXPECT_LT(angleDeg(pose.T_camera_board.R(), R_cv), 1e-4) << k;
    EXPECT_LT((pose.T_camera_board.t() - truth.t()).norm(), 0.005) << k;
    EXPECT_LT(angleDeg(pose.T_camera_board.R(), truth.R()), 1.5) << k;
    BoardPoseOptions linear;
    linear.refine = false;
    const BoardPose linear_pose = boardPose(board.cornersWorld(), xy, cam.fx, linear);
    EXPECT_LT((linear_pose.T_camera_board.t() - truth.t()).norm(), 0.01) << k;
    EXPECT_LE(pose.rms_px, linear_pose.rms_px + 1e-12) << k;
  }
}

std::vector<double> readNumbers(const std::string& path) {
  std::ifstream in(path);
  std::vector<double> v;
  double x;
  while (in >> x) v.push_back(x);
  return v;
}

// Zhang's original data: with his published intrinsics and distortion, the pose of each of the 5
// views from the homography (refined) must match his published extrinsics. His extrinsics come
// from a joint optimisation of all parameters, ours from the corners of one view with those
// parameters fixed: both minimise the same error, so they agree to the rounding of the published
// numbers and the per-view optimum: 0.1 degree and 0.5 % of the distance (about 13 model units).
TEST(HomographyPose, MatchesZhangsPublishedExtrinsics) {
  SLAMCMP_REQUIRE_SHARED(shared);
  const std::string dir = shared + "/calibration/zhang/";
  const auto result = readNumbers(dir + "calibration-result-zhang-withdistortion.txt");
  ASSERT_EQ(result.size(), 5u + 2u + 5u * 12u);
  CameraModel cam;
  cam.width = 640, cam.height = 480;
  cam.fx = result[0], cam.skew = result[1], cam.fy = result[2], cam.cx = result[3], cam.cy = result[4];
  cam.distortion[0] = result[5], cam.distortion[1] = result[6];
  const auto model = readNumbers(dir + "Model.txt");
  std::vector<Vec3> p_board;
  for (size_t i = 0; i + 1 < model.size(); i += 2) p_board.emplace_back(model[i], model[i + 1], 0);
  for (int view = 0; view < 5; ++view) {
    const auto data = readNumbers(dir + "data" + std::to_string(view + 1) + ".txt");
    ASSERT_EQ(data.size(), 2 * p_board.size());
    std::vector<Vec2> xy;
    for (size_t i = 0; i < data.size(); i += 2) xy.push_back(cam.undistortPixel(Vec2(data[i], data[i + 1])));
    const BoardPose pose = boardPose(p_board, xy, cam.fx, {});
    const double* r = &result[7 + 12 * view];
    Mat3 R;
    R << r[0], r[1], r[2], r[3], r[4], r[5], r[6], r[7], r[8];
    const Vec3 t(r[9], r[10], r[11]);
    EXPECT_LT(angleDeg(pose.T_camera_board.R(), nearestRotation(R)), 0.1) << "view " << view + 1;
    EXPECT_LT((pose.T_camera_board.t() - t).norm(), 0.005 * t.norm()) << "view " << view + 1;
    EXPECT_LT(pose.rms_px, 1.0) << "view " << view + 1;
  }
}

}  // namespace
}  // namespace slamcmp
