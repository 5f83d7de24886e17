// hybrid/board_corner_measurement on rendered tv1 frames against the ground truth: corners tracked
// into the next frame where the filter predicts them, and a prediction a square off along the
// diagonal (every corner started on a neighbour that looks alike, where Lucas-Kanade stays)
// refused rather than measured with its neighbour's identity.
#include "hybrid/board_corner_measurement.h"

#include <algorithm>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "core/chessboard.h"
#include "tests/rendered_preset.h"

namespace slamcmp {
namespace {

class BoardCornerMeasurerTv1 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { tv1_ = std::make_unique<test::RenderedPreset>(test::renderPreset("tv1", 2)); }
  static void TearDownTestSuite() { tv1_.reset(); }

  // A filter at T_world_camera whose position std is `position_sigma` (m), its orientation sure.
  static EkfState filterAt(const SE3& T_world_camera, double position_sigma) {
    Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Identity() * 1e-6;
    P.topLeftCorner<3, 3>() = Mat3::Identity() * position_sigma * position_sigma;
    P.block<4, 4>(EkfState::kQ, EkfState::kQ) = Eigen::Matrix4d::Identity() * 1e-12;
    EkfState s;
    s.reset(T_world_camera, P);
    return s;
  }

  // The corners measured in frame 1 by a measurer that measured frame 0 from the true pose, with
  // the filter's prior for frame 1 at T_world_camera; each with its distance to where the true
  // pose projects the corner it is said to be, pixels. `outside_gates`: the board the measurer
  // found where predicted but outside its gates.
  static std::vector<double> measureSecondFrame(const SE3& T_world_camera, double position_sigma,
                                                std::vector<cv::Point2f>* outside_gates = nullptr) {
    BoardCornerMeasurer measurer(tv1_->camera, tv1_->target, BoardCornerMeasurementOptions());
    const test::PosedFrame& first = tv1_->frames.at(0);
    EXPECT_EQ(static_cast<int>(measurer.measure(filterAt(first.T_world_camera, 1e-5), first.grey).observations.size()),
              tv1_->target.numCorners());
    const test::PosedFrame& second = tv1_->frames.at(1);
    const BoardCornerMeasurement m = measurer.measure(filterAt(T_world_camera, position_sigma), second.grey);
    if (outside_gates) *outside_gates = measurer.boardOutsideGates();
    const std::vector<cv::Point2f> truth = projectBoardCorners(tv1_->camera, tv1_->target, second.T_world_camera);
    std::vector<double> errors;
    for (size_t k = 0; k < m.observations.size(); ++k) {
      const cv::Point2f& t = truth[m.corner_ids[k]];
      errors.push_back((m.observations[k].z - Vec2(t.x, t.y)).norm());
    }
    return errors;
  }

  static std::unique_ptr<test::RenderedPreset> tv1_;
};

std::unique_ptr<test::RenderedPreset> BoardCornerMeasurerTv1::tv1_;

// A fifth of a square of position std: each corner's 3-sigma half axis over half a square, wide
// enough that a square-off prediction is not refined where it stands (corners.max_predicted_search,
// 0.5 squares), narrow enough that the gate (4.3 sigma) refuses a corner a square from its prediction.
double positionSigma(const ChessboardTarget& target) { return target.square_size / 5.0; }

TEST_F(BoardCornerMeasurerTv1, TracksEveryCornerFromATruePrediction) {
  std::vector<cv::Point2f> outside_gates;
  const std::vector<double> errors =
      measureSecondFrame(tv1_->frames.at(1).T_world_camera, positionSigma(tv1_->target), &outside_gates);
  EXPECT_EQ(static_cast<int>(errors.size()), tv1_->target.numCorners());
  for (double e : errors) EXPECT_LT(e, 0.3);
  EXPECT_TRUE(outside_gates.empty());
}

// The prior a square off along the board's diagonal (the camera moved by one square in x and y):
// every corner is predicted where its diagonal neighbour is, which looks alike (a neighbour along
// a row has its colours swapped), and Lucas-Kanade started there stays on it, its innovation
// nought. Tracked also from where the corners were, the two starts disagree: no corner is
// measured with its neighbour's identity (a board search where the filter predicts it finds the
// board 1.4 squares from the prediction, beyond the gate, and hands it on as such).
TEST_F(BoardCornerMeasurerTv1, RefusesAPredictionASquareOff) {
  const SE3& truth = tv1_->frames.at(1).T_world_camera;
  const double s = tv1_->target.square_size;
  std::vector<cv::Point2f> outside_gates;
  const std::vector<double> errors =
      measureSecondFrame(SE3(truth.R(), truth.t() + Vec3(s, s, 0)), positionSigma(tv1_->target), &outside_gates);
  EXPECT_TRUE(errors.empty()) << errors.size() << " corners measured";
  const double square_px = 20;  // tv1's squares are 21-28 px: a wrong identity is a square off
  for (double e : errors) EXPECT_LT(e, 0.5 * square_px) << "a corner measured with another's identity";
  // The board found there is handed on (the tracker then widens the filter and takes it), each
  // corner with its own identity.
  ASSERT_EQ(static_cast<int>(outside_gates.size()), tv1_->target.numCorners());
  const std::vector<cv::Point2f> at_truth =
      projectBoardCorners(tv1_->camera, tv1_->target, tv1_->frames.at(1).T_world_camera);
  for (size_t k = 0; k < outside_gates.size(); ++k) EXPECT_LT(cv::norm(outside_gates[k] - at_truth[k]), 0.3) << k;
}

// The corners checked first are the hull's: the whole board's four corners (not one column, as a
// stride through the row-major list gave: 0, 9, ..., 45 of a 9 x 6 board), and a strip's own.
TEST(SpotCheckCorners, TakeTheHullOfTheTrackedCorners) {
  const int cols = 9, rows = 6;
  std::vector<int> board(cols * rows);
  for (int id = 0; id < cols * rows; ++id) board[id] = id;
  std::vector<int> spot = spotCheckCorners(board, cols);
  std::sort(spot.begin(), spot.end());
  EXPECT_EQ(spot, (std::vector<int>{0, 8, 45, 53}));
  std::vector<int> strip;  // columns 3..8 in view, listed as tracking lists them
  for (int id = 0; id < cols * rows; ++id)
    if (id % cols >= 3) strip.push_back(id);
  spot = spotCheckCorners(strip, cols);
  std::sort(spot.begin(), spot.end());
  EXPECT_EQ(spot, (std::vector<int>{3, 8, 48, 53}));
  EXPECT_TRUE(spotCheckCorners({}, cols).empty());
}

}  // namespace
}  // namespace slamcmp
