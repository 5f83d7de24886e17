// hybrid/board_corner_measurement on rendered tv1 frames against the ground truth: corners tracked
// into the next frame where the filter predicts them, and a prediction a whole square off (every
// corner started on its neighbour, where Lucas-Kanade stays) refused rather than measured with
// its neighbour's identity.
#include "hybrid/board_corner_measurement.h"

#include <cmath>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "core/chessboard.h"
#include "core/sequence.h"
#include "datasets/synth_sequence.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

struct PosedFrame {
  cv::Mat grey;
  SE3 T_world_camera;  // ground truth
};

class BoardCornerMeasurerTv1 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    test::TempDir dir;
    SynthOptions options;
    options.preset = "tv1";
    options.frames = 2;
    writeSyntheticSequence(options, dir.file("tv1"));
    Sequence seq = openSequence(dir.file("tv1"));
    ASSERT_TRUE(seq.camera && seq.target && seq.groundtruth);
    camera_ = std::make_unique<CameraModel>(*seq.camera);
    target_ = std::make_unique<ChessboardTarget>(*seq.target);
    frames_ = std::make_unique<std::vector<PosedFrame>>();
    for (Frame f; seq.frames->next(&f);)
      for (const StampedPose& p : *seq.groundtruth)
        if (std::abs(p.timestamp - f.timestamp) < 1e-6) frames_->push_back({f.grey, p.T_world_camera});
    ASSERT_EQ(frames_->size(), 2u);
  }
  static void TearDownTestSuite() {
    frames_.reset();
    target_.reset();
    camera_.reset();
  }

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
  // pose projects the corner it is said to be, pixels.
  static std::vector<double> measureSecondFrame(const SE3& T_world_camera, double position_sigma) {
    BoardCornerMeasurer measurer(*camera_, *target_, BoardCornerMeasurementOptions());
    const PosedFrame& first = (*frames_)[0];
    EXPECT_EQ(measurer.measure(filterAt(first.T_world_camera, 1e-5), first.grey).observations.size(),
              static_cast<size_t>(target_->cols * target_->rows));
    const PosedFrame& second = (*frames_)[1];
    const BoardCornerMeasurement m = measurer.measure(filterAt(T_world_camera, position_sigma), second.grey);
    const std::vector<cv::Point2f> truth = projectBoardCorners(*camera_, *target_, second.T_world_camera);
    std::vector<double> errors;
    for (size_t k = 0; k < m.observations.size(); ++k) {
      const cv::Point2f& t = truth[m.corner_ids[k]];
      errors.push_back((m.observations[k].z - Vec2(t.x, t.y)).norm());
    }
    return errors;
  }

  static std::unique_ptr<CameraModel> camera_;
  static std::unique_ptr<ChessboardTarget> target_;
  static std::unique_ptr<std::vector<PosedFrame>> frames_;
};

std::unique_ptr<CameraModel> BoardCornerMeasurerTv1::camera_;
std::unique_ptr<ChessboardTarget> BoardCornerMeasurerTv1::target_;
std::unique_ptr<std::vector<PosedFrame>> BoardCornerMeasurerTv1::frames_;

// A sixth of a square of position std: each corner's 3-sigma half axis about half a square, wide
// enough that a square-off prediction is not refined where it stands, narrow enough that the gate
// refuses a corner a square from its prediction.
double positionSigma(const ChessboardTarget& target) { return target.square_size / 6.0; }

TEST_F(BoardCornerMeasurerTv1, TracksEveryCornerFromATruePrediction) {
  const std::vector<double> errors = measureSecondFrame((*frames_)[1].T_world_camera, positionSigma(*target_));
  EXPECT_EQ(errors.size(), static_cast<size_t>(target_->cols * target_->rows));
  for (double e : errors) EXPECT_LT(e, 0.3);
}

// The prior a square off along the board's diagonal (the camera moved by one square in x and y):
// every corner is predicted where its diagonal neighbour is, which looks alike (a neighbour along
// a row has its colours swapped), and Lucas-Kanade started there stays on it, its innovation
// nought. Tracked also from where the corners were, the two starts disagree: no corner is
// measured with its neighbour's identity (a board search where the filter predicts it finds the
// board a square and a half from the prediction, beyond the gate).
TEST_F(BoardCornerMeasurerTv1, RefusesAPredictionASquareOff) {
  const SE3& truth = (*frames_)[1].T_world_camera;
  const SE3 square_off(truth.R(), truth.t() + Vec3(target_->square_size, target_->square_size, 0));
  const std::vector<double> errors = measureSecondFrame(square_off, positionSigma(*target_));
  for (double e : errors) EXPECT_LT(e, 0.3) << "a corner measured with another's identity";
}

}  // namespace
}  // namespace slamcmp
