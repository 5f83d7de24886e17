// Chessboard detection on real images and the board frame of SPEC section 2: the same physical
// corner is the origin at any camera roll, and Z points into the board.
#include "core/chessboard.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/sequence.h"
#include "core/target.h"
#include "core/trajectory.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

const ChessboardTarget kBoard9x6{9, 6, 0.04};  // vamr: 4 cm squares

std::vector<std::string> opencvLeftImages() {
  return {"left01", "left02", "left03", "left04", "left05", "left06", "left07",
          "left08", "left09", "left11", "left12", "left13", "left14"};
}

// vamr frames (1-based, as the file names), spread over the sequence.
std::vector<int> vamrFrames() { return {1, 120, 250, 400, 560, 736}; }

std::string vamrImage(const std::string& data, int frame) {
  char name[64];
  std::snprintf(name, sizeof name, "/vamr_checkerboard/images/img_%04d.jpg", frame);
  return data + name;
}

// Pose of the board in the camera (R_camera_world, t) by solvePnP on the detected corners.
void boardPose(const CameraModel& camera, const ChessboardTarget& t,
               const std::vector<cv::Point2f>& uv, Mat3* R_camera_world, Vec3* t_camera_world) {
  std::vector<cv::Point3d> object;
  for (const Vec3& p : t.cornersWorld()) object.emplace_back(p.x(), p.y(), p.z());
  cv::Mat rvec, tvec;
  ASSERT_TRUE(cv::solvePnP(object, uv, camera.cameraMatrix(), camera.distortionVector(), rvec, tvec,
                           false, cv::SOLVEPNP_ITERATIVE));
  *R_camera_world =
      rotationFromRotvec(Vec3(rvec.at<double>(0), rvec.at<double>(1), rvec.at<double>(2)));
  *t_camera_world = Vec3(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
}

class OpenCVLeftImages : public ::testing::TestWithParam<std::string> {};

TEST_P(OpenCVLeftImages, FindsAllCornersInOrder) {
  SLAMCMP_REQUIRE_SHARED(data);
  const cv::Mat grey = readGreyImage(data + "/calibration/opencv_left/" + GetParam() + ".jpg");
  ASSERT_FALSE(grey.empty());
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(grey, kBoard9x6, &uv));
  ASSERT_EQ(uv.size(), 54u);
  // A grid: neighbours along X and along Y are about one square apart, never folded back.
  const double spacing = minCornerSpacing(kBoard9x6, uv);
  EXPECT_GT(spacing, 10.0);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i + 1 < 9; ++i)
      EXPECT_LT(cv::norm(uv[j * 9 + i + 1] - uv[j * 9 + i]), 3.0 * spacing) << i << "," << j;
}

INSTANTIATE_TEST_SUITE_P(Calibration, OpenCVLeftImages, ::testing::ValuesIn(opencvLeftImages()));

// On vamr the ground truth was computed from the board in SPEC section 2's frame: the pose from
// our corners must agree with it, which pins down the origin corner and the handedness.
class VamrFrames : public ::testing::TestWithParam<int> {};

TEST_P(VamrFrames, DetectedBoardGivesTheGroundTruthPose) {
  SLAMCMP_REQUIRE_SHARED(data);
  const int frame = GetParam();
  const CameraModel camera = readCameraYaml(data + "/vamr_checkerboard/camera.yaml");
  const ChessboardTarget target = readTargetYaml(data + "/vamr_checkerboard/target.yaml");
  const Trajectory gt = readTrajectory(data + "/vamr_checkerboard/groundtruth.txt");
  ASSERT_EQ(gt.size(), 736u);
  const cv::Mat grey = readGreyImage(vamrImage(data, frame));
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(grey, target, &uv));
  ASSERT_EQ(uv.size(), 54u);
  Mat3 R_camera_world;
  Vec3 t_camera_world;
  boardPose(camera, target, uv, &R_camera_world, &t_camera_world);
  // Z = X x Y points into the board, away from the camera; the board is in front.
  EXPECT_GT(R_camera_world(2, 2), 0.0);
  EXPECT_GT(t_camera_world.z(), 0.0);
  const SE3 T_world_camera = SE3(R_camera_world, t_camera_world).inverse();
  const SE3& T_gt = gt[frame - 1].T_world_camera;
  EXPECT_LT((T_world_camera.t() - T_gt.t()).norm(), 0.005) << "metres";
  EXPECT_LT(rotationAngle(T_gt.R().transpose() * T_world_camera.R()), 0.5 * M_PI / 180.0);
}

INSTANTIATE_TEST_SUITE_P(Sequence, VamrFrames, ::testing::ValuesIn(vamrFrames()));

// Where a pixel of the rotated image lies in the original (w x h) image.
cv::Point2f unrotate(const cv::Point2f& p, int code, int w, int h) {
  switch (code) {
    case cv::ROTATE_90_CLOCKWISE:
      return {p.y, h - 1 - p.x};
    case cv::ROTATE_180:
      return {w - 1 - p.x, h - 1 - p.y};
    default:  // ROTATE_90_COUNTERCLOCKWISE
      return {w - 1 - p.y, p.x};
  }
}

struct RollCase {
  std::string image;  // relative to the shared datasets
  int rotate_code;
  std::string name;
};

// gtest prints the parameter by its name.
void PrintTo(const RollCase& c, std::ostream* os) { *os << c.name; }

class CameraRoll : public ::testing::TestWithParam<RollCase> {};

TEST_P(CameraRoll, OriginIsTheSamePhysicalCornerAtEveryRoll) {
  SLAMCMP_REQUIRE_SHARED(data);
  const RollCase& roll = GetParam();
  const cv::Mat grey = readGreyImage(data + roll.image);
  ASSERT_FALSE(grey.empty());
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(grey, kBoard9x6, &uv));
  cv::Mat rotated;
  cv::rotate(grey, rotated, roll.rotate_code);
  std::vector<cv::Point2f> uv_rotated;
  ASSERT_TRUE(detectChessboard(rotated, kBoard9x6, &uv_rotated));
  ASSERT_EQ(uv_rotated.size(), uv.size());
  // Corner 0 first (the origin), then every corner: same physical corner, same index.
  EXPECT_LT(cv::norm(unrotate(uv_rotated[0], roll.rotate_code, grey.cols, grey.rows) - uv[0]), 0.5);
  std::vector<cv::Point2f> uv_back;
  for (size_t k = 0; k < uv.size(); ++k) {
    uv_back.push_back(unrotate(uv_rotated[k], roll.rotate_code, grey.cols, grey.rows));
    EXPECT_LT(cv::norm(uv_back.back() - uv[k]), 0.5) << "corner " << k;
  }
  // Handedness in the rotated image itself: the board normal Z points away from the camera.
  if (roll.image.find("vamr") != std::string::npos) {
    CameraModel rolled = readCameraYaml(data + "/vamr_checkerboard/camera.yaml");
    // The rotated image's camera: same lens turned about its axis. Only the normal's sign is
    // checked, so an approximate model (centre moved, focal lengths swapped) is enough.
    if (roll.rotate_code != cv::ROTATE_180) {
      std::swap(rolled.fx, rolled.fy);
      std::swap(rolled.width, rolled.height);
    }
    rolled.cx = (rotated.cols - 1) / 2.0;
    rolled.cy = (rotated.rows - 1) / 2.0;
    Mat3 R_camera_world;
    Vec3 t_camera_world;
    boardPose(rolled, kBoard9x6, uv_rotated, &R_camera_world, &t_camera_world);
    EXPECT_GT(R_camera_world(2, 2), 0.0);
    EXPECT_GT(t_camera_world.z(), 0.0);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Rolls, CameraRoll,
    ::testing::Values(
        RollCase{"/vamr_checkerboard/images/img_0001.jpg", cv::ROTATE_90_CLOCKWISE, "vamr_90"},
        RollCase{"/vamr_checkerboard/images/img_0001.jpg", cv::ROTATE_180, "vamr_180"},
        RollCase{"/vamr_checkerboard/images/img_0001.jpg", cv::ROTATE_90_COUNTERCLOCKWISE,
                 "vamr_270"},
        RollCase{"/calibration/opencv_left/left01.jpg", cv::ROTATE_90_CLOCKWISE, "left01_90"},
        RollCase{"/calibration/opencv_left/left01.jpg", cv::ROTATE_180, "left01_180"},
        RollCase{"/calibration/opencv_left/left01.jpg", cv::ROTATE_90_COUNTERCLOCKWISE,
                 "left01_270"}),
    [](const auto& info) { return info.param.name; });

TEST(Chessboard, MirroredAndReversedOrdersAreFixed) {
  SLAMCMP_REQUIRE_SHARED(data);
  const cv::Mat grey = readGreyImage(vamrImage(data, 1));
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(grey, kBoard9x6, &uv));
  const int cols = kBoard9x6.cols, rows = kBoard9x6.rows;
  std::vector<cv::Point2f> mirrored_x(uv.size()), mirrored_y(uv.size()),
      reversed(uv.rbegin(), uv.rend());
  for (int j = 0; j < rows; ++j)
    for (int i = 0; i < cols; ++i) {
      mirrored_x[j * cols + i] = uv[j * cols + (cols - 1 - i)];
      mirrored_y[j * cols + i] = uv[(rows - 1 - j) * cols + i];
    }
  for (auto* order : {&mirrored_x, &mirrored_y, &reversed}) {
    ASSERT_TRUE(orderChessboardCorners(grey, kBoard9x6, *order));
    for (size_t k = 0; k < uv.size(); ++k) EXPECT_EQ((*order)[k], uv[k]) << "corner " << k;
  }
}

// A drawn chessboard (40 px squares, the top-left square black, white margin) turned by `degrees`
// about the centre of a 640x480 image; *uv gets its inner corners row by row from the corner that
// was top-left before the turn.
cv::Mat drawnBoard(const ChessboardTarget& t, double degrees, std::vector<cv::Point2f>* uv) {
  constexpr int kSquare = 40;
  cv::Mat board(480, 640, CV_8UC1, cv::Scalar(230));
  const cv::Point origin(320 - (t.cols + 1) * kSquare / 2, 240 - (t.rows + 1) * kSquare / 2);
  for (int b = 0; b <= t.rows; ++b)
    for (int a = 0; a <= t.cols; ++a)
      if ((a + b) % 2 == 0)
        cv::rectangle(board, cv::Rect(origin.x + a * kSquare, origin.y + b * kSquare, kSquare, kSquare),
                      cv::Scalar(25), cv::FILLED);
  const cv::Mat M = cv::getRotationMatrix2D(cv::Point2f(319.5f, 239.5f), degrees, 1.0);
  cv::Mat turned;
  cv::warpAffine(board, turned, M, board.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT, cv::Scalar(230));
  uv->clear();
  for (int j = 0; j < t.rows; ++j)
    for (int i = 0; i < t.cols; ++i) {
      // A corner is the point between pixels: pixel centres are at integer coordinates.
      const cv::Vec3d p(origin.x + (i + 1) * kSquare - 0.5, origin.y + (j + 1) * kSquare - 0.5, 1.0);
      const cv::Vec2d q = cv::Matx23d(M) * p;
      uv->emplace_back(static_cast<float>(q[0]), static_cast<float>(q[1]));
    }
  return turned;
}

std::vector<cv::Point2f> reversedOrder(const std::vector<cv::Point2f>& uv) { return {uv.rbegin(), uv.rend()}; }

const ChessboardTarget kBoard8x6{8, 6, 0.03};  // symmetric: both counts even

// The detector finds the drawn symmetric board; its origin is one of the two 180 degree turns'.
TEST(SymmetricBoard, DetectedCornersAreTheGridInOneOfItsTurns) {
  std::vector<cv::Point2f> truth;
  const cv::Mat grey = drawnBoard(kBoard8x6, 25, &truth);
  std::vector<cv::Point2f> uv;
  ASSERT_TRUE(detectChessboard(grey, kBoard8x6, &uv));
  ASSERT_EQ(uv.size(), 48u);
  const std::vector<cv::Point2f> truth_turned = reversedOrder(truth);
  const auto& expected = cv::norm(uv[0] - truth[0]) < cv::norm(uv[0] - truth_turned[0]) ? truth : truth_turned;
  for (size_t k = 0; k < uv.size(); ++k) EXPECT_LT(cv::norm(uv[k] - expected[k]), 0.3) << "corner " << k;
}

// With no reference the convention decides: of the two turns, corner 0 nearest the image's
// top-left corner, whatever order the corners came in.
TEST(SymmetricBoard, ConventionPutsTheOriginNearestTheTopLeft) {
  for (const double degrees : {0.0, 25.0, 100.0, 180.0, 250.0}) {
    std::vector<cv::Point2f> truth;
    const cv::Mat grey = drawnBoard(kBoard8x6, degrees, &truth);
    const std::vector<cv::Point2f> truth_turned = reversedOrder(truth);
    const auto& expected = cv::norm(truth[0]) < cv::norm(truth_turned[0]) ? truth : truth_turned;
    for (auto order : {truth, truth_turned}) {
      chooseSymmetricOrder(kBoard8x6, order);
      EXPECT_EQ(order, expected) << degrees << " degrees";
    }
    std::vector<cv::Point2f> uv;
    ASSERT_TRUE(detectChessboard(grey, kBoard8x6, &uv)) << degrees << " degrees";
    EXPECT_LT(cv::norm(uv[0] - expected[0]), 0.3) << degrees << " degrees";
  }
}

// With a reference (last frame's corners, or projected from the last pose: a few pixels off),
// the turn nearest it wins, even where the convention would pick the other one.
TEST(SymmetricBoard, ReferenceKeepsTheOrigin) {
  std::vector<cv::Point2f> truth;
  drawnBoard(kBoard8x6, 170, &truth);  // the convention picks the turned order here
  std::vector<cv::Point2f> reference = truth;
  cv::RNG rng(3);
  for (auto& p : reference) p += cv::Point2f(12.0f + rng.uniform(-5.f, 5.f), -8.0f + rng.uniform(-5.f, 5.f));
  for (auto order : {truth, reversedOrder(truth)}) {
    chooseSymmetricOrder(kBoard8x6, order, reference);
    EXPECT_EQ(order, truth);
    chooseSymmetricOrder(kBoard8x6, order, reversedOrder(reference));
    EXPECT_EQ(order, reversedOrder(truth));
  }
  std::vector<cv::Point2f> convention = truth;
  chooseSymmetricOrder(kBoard8x6, convention);
  EXPECT_EQ(convention, reversedOrder(truth));
}

// A square board (6x6) also looks the same after a quarter turn: the reference picks among four.
TEST(SymmetricBoard, SquareBoardHasFourTurns) {
  const ChessboardTarget square{6, 6, 0.03};
  std::vector<cv::Point2f> truth;
  drawnBoard(square, 30, &truth);
  std::vector<cv::Point2f> quarter(truth.size());
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 6; ++i) quarter[j * 6 + i] = truth[i * 6 + (5 - j)];
  std::vector<cv::Point2f> order = quarter;
  chooseSymmetricOrder(square, order, truth);
  EXPECT_EQ(order, truth);
  order = truth;
  chooseSymmetricOrder(square, order, quarter);
  EXPECT_EQ(order, quarter);
}

// An asymmetric board's order is fixed by the square colours: never renumbered.
TEST(SymmetricBoard, AsymmetricBoardIsLeftAlone) {
  std::vector<cv::Point2f> truth;
  drawnBoard(kBoard9x6, 0, &truth);
  std::vector<cv::Point2f> order = reversedOrder(truth);
  chooseSymmetricOrder(kBoard9x6, order, truth);
  EXPECT_EQ(order, reversedOrder(truth));
}

TEST(SymmetricBoard, ProjectedCornersForTheReference) {
  CameraModel camera;
  camera.width = 640;
  camera.height = 480;
  camera.fx = camera.fy = 500;
  camera.cx = 319.5;
  camera.cy = 239.5;
  const SE3 T_world_camera(Mat3::Identity(), Vec3(0.1, 0.07, -0.5));  // 0.5 m in front of the board
  const std::vector<cv::Point2f> uv = projectBoardCorners(camera, kBoard8x6, T_world_camera);
  ASSERT_EQ(uv.size(), 48u);
  const Vec2 last = camera.project(T_world_camera.inverse() * kBoard8x6.cornerWorld(7, 5));
  EXPECT_NEAR(uv[47].x, last.x(), 1e-3);
  EXPECT_NEAR(uv[47].y, last.y(), 1e-3);
  EXPECT_NEAR(uv[0].x, 319.5 - 0.1 * 1000, 1e-3);  // (0, 0, 0) seen 0.1 m left, 0.07 m up, 0.5 m away
  EXPECT_NEAR(uv[0].y, 239.5 - 0.07 * 1000, 1e-3);
  // Behind the camera: no reference.
  EXPECT_TRUE(projectBoardCorners(camera, kBoard8x6, SE3(Mat3::Identity(), Vec3(0, 0, 0.5))).empty());
}

TEST(Chessboard, NoBoardInAFlatOrNoisyImage) {
  std::vector<cv::Point2f> uv;
  EXPECT_FALSE(detectChessboard(cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)), kBoard9x6, &uv));
  cv::Mat noise(480, 640, CV_8UC1);
  cv::randu(noise, 0, 255);
  EXPECT_FALSE(detectChessboard(noise, kBoard9x6, &uv));
  EXPECT_TRUE(uv.empty());
}

}  // namespace
}  // namespace slamcmp
