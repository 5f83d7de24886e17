// Map management: a feature judged by its record (SceneLib: after min_attempts, deleted if matched
// in under min_success_ratio of them) and, with map.max_misses_in_a_row, by its last attempts.
#include <optional>
#include <random>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "ekf/ekf_slam.h"
#include "tests/ekf/plane_render.h"

namespace slamcmp {
namespace {

// A board-free map started by a camera at rest before a wall of grey shapes and matched in 10
// frames (its record: matched every time), then shown a blank view (a hand over the lens).
class MapOverABlankView {
 public:
  explicit MapOverABlankView(int max_misses_in_a_row) : camera_(test::testCamera()) {
    EkfSlamOptions options;
    options.map.max_misses_in_a_row = max_misses_in_a_row;
    options.motion.sigma_a = 0.1;  // at rest: every feature's search stays small enough to be made
    options.motion.sigma_alpha = 0.1;
    slam_.emplace(camera_, options, /*board_free=*/true);
    slam_->reset(SE3(Mat3::Identity(), Vec3(0.0, 0.0, -1.0)), Eigen::Matrix<double, 13, 13>::Identity() * 1e-8);
    wall_ = cv::Mat(camera_.height, camera_.width, CV_8U, cv::Scalar(128));
    std::mt19937 rng(5);
    std::uniform_int_distribution<int> x(0, camera_.width - 1), y(0, camera_.height - 1), side(4, 20), grey(0, 255);
    for (int i = 0; i < 1500; ++i)
      cv::rectangle(wall_, cv::Rect(x(rng), y(rng), side(rng), side(rng)), cv::Scalar(grey(rng)), -1);
    for (int i = 0; i < 10; ++i) step(wall_);
  }
  void blankFrame() { step(cv::Mat(wall_.size(), CV_8U, cv::Scalar(128))); }
  void wallFrame() { step(wall_); }
  const std::vector<MapFeature>& features() const { return slam_->features(); }

 private:
  void step(const cv::Mat& grey) {
    slam_->predict(0.1);
    const FrameMeasurement m = slam_->measure(grey);
    slam_->updateMap(grey, m.visible);
  }
  CameraModel camera_;
  std::optional<EkfSlam> slam_;
  cv::Mat wall_;
};

TEST(MapManagement, AFeatureMissedInARowIsDeletedWhateverItsRecord) {
  MapOverABlankView record_only(0), in_a_row(4);
  const size_t mapped = record_only.features().size();
  ASSERT_GE(mapped, 8u);
  ASSERT_EQ(in_a_row.features().size(), mapped);
  // Three blank frames, the wall again (a match ends the misses), then four more.
  for (int frame = 1; frame <= 8; ++frame) {
    if (frame == 4) {
      record_only.wallFrame();
      in_a_row.wallFrame();
    } else {
      record_only.blankFrame();
      in_a_row.blankFrame();
    }
    const int misses = frame < 4 ? frame : frame == 4 ? 0 : frame - 4;
    // Matched 9 times, missed up to 7: the record keeps every feature.
    EXPECT_EQ(record_only.features().size(), mapped) << frame;
    EXPECT_EQ(in_a_row.features().size(), misses < 4 ? mapped : 0u) << frame;
    for (const MapFeature& f : in_a_row.features()) EXPECT_EQ(f.misses_in_a_row, misses) << f.id;
  }
}

}  // namespace
}  // namespace slamcmp
