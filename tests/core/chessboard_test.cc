// Chessboard detection on real images and the board frame of SPEC section 2: the same physical
// corner is the origin at any camera roll, and Z points into the board.
#include "core/chessboard.h"

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
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
