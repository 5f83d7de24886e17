#include "core/self_calibration.h"

#include <cmath>

#include <opencv2/calib3d.hpp>

#include "core/chessboard.h"
#include "core/error.h"
#include "core/progress.h"

namespace slamcmp {

void SelfCalibrationOptions::check() const {
  if (min_views < 3) throw OptionError("min_views", "must be >= 3 (Zhang needs three views)");
  if (max_views < min_views) throw OptionError("max_views", "must be >= min_views");
  if (max_frames < 1) throw OptionError("max_frames", "must be >= 1");
  if (!(min_view_change >= 0)) throw OptionError("min_view_change", "must be >= 0");
  if (!(max_rms_px > 0)) throw OptionError("max_rms_px", "must be positive");
  if (distortion_terms != 4 && distortion_terms != 5) throw OptionError("distortion_terms", "must be 4 or 5");
}

SelfCalibrator::SelfCalibrator(const ChessboardTarget& target, cv::Size image_size,
                               const SelfCalibrationOptions& options)
    : target_(target), image_size_(image_size), options_(options) {}

bool SelfCalibrator::addView(const std::vector<cv::Point2f>& uv) {
  if (full()) return false;
  const double diagonal = std::hypot(image_size_.width, image_size_.height);
  const double min_change2 = std::pow(options_.min_view_change * diagonal, 2);
  for (const auto& kept : views_) {
    double sum = 0;
    for (size_t i = 0; i < uv.size(); ++i) {
      const cv::Point2f d = uv[i] - kept[i];
      sum += d.dot(d);
    }
    if (sum / static_cast<double>(uv.size()) < min_change2) return false;
  }
  views_.push_back(uv);
  return true;
}

std::optional<CalibrationResult> SelfCalibrator::calibrate() const {
  if (numViews() < options_.min_views) return std::nullopt;
  std::vector<cv::Point3f> board;
  for (const Vec3& p : target_.cornersWorld())
    board.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.f);
  const std::vector<std::vector<cv::Point3f>> object(views_.size(), board);
  cv::Mat K, dist;
  std::vector<cv::Mat> rvecs, tvecs;
  int flags = 0;
  if (options_.distortion_terms == 4) flags |= cv::CALIB_FIX_K3;
  const double rms = cv::calibrateCamera(object, views_, image_size_, K, dist, rvecs, tvecs, flags);
  if (!std::isfinite(rms) || rms > options_.max_rms_px) return std::nullopt;
  CalibrationResult result;
  result.camera = CameraModel::fromOpenCV(K, dist.reshape(1, 1).colRange(0, options_.distortion_terms), image_size_);
  result.rms_px = rms;
  result.views = numViews();
  return result;
}

CalibrationResult calibrateFromFrames(FrameSource& frames, const ChessboardTarget& target, cv::Size image_size,
                                      const SelfCalibrationOptions& options, const std::string& where) {
  SelfCalibrator calibrator(target, image_size, options);
  Progress progress("calibrate", frames.size());
  Frame frame;
  int done = 0, with_board = 0;
  std::vector<cv::Point2f> last_uv;  // the last view's corners
  while (!calibrator.full() && frames.next(&frame)) {
    progress.update(++done);
    std::vector<cv::Point2f> uv;
    if (frame.grey.empty()) continue;
    // Speed does not matter here: where the classic detector fails (strong distortion, small
    // squares) OpenCV's sector-based detector gets another try.
    if (!detectChessboard(frame.grey, target, &uv)) {
      if (!cv::findChessboardCornersSB(frame.grey, cv::Size(target.cols, target.rows), uv) ||
          static_cast<int>(uv.size()) != target.numCorners())
        continue;
      refineChessboardCorners(frame.grey, target, uv);
      if (!orderChessboardCorners(frame.grey, target, uv)) continue;
    }
    // A symmetric board: the origin nearest the last view's, so that a view turned by 180 degrees
    // is not taken for a new one.
    chooseSymmetricOrder(target, uv, last_uv);
    last_uv = uv;
    ++with_board;
    calibrator.addView(uv);
  }
  progress.finish();
  const auto result = calibrator.calibrate();
  if (!result)
    throw InputError(where, "the " + std::to_string(target.cols) + "x" + std::to_string(target.rows) +
                                " board was found in " + std::to_string(with_board) + " of " + std::to_string(done) +
                                " frames, giving " + std::to_string(calibrator.numViews()) +
                                " distinct views; calibration needs " + std::to_string(options.min_views) +
                                " views and a reprojection error under " + std::to_string(options.max_rms_px) + " px");
  return *result;
}

}  // namespace slamcmp
