#include "core/self_calibration.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>

#include "core/chessboard.h"
#include "core/distortion_fold.h"
#include "core/error.h"
#include "core/format_string.h"
#include "core/progress.h"

namespace slamcmp {

void SelfCalibrationOptions::check() const {
  if (max_late_poses < 0) throw OptionError("max_late_poses", "must be >= 0");
  if (min_views < 3) throw OptionError("min_views", "must be >= 3 (Zhang needs three views)");
  if (max_views < min_views) throw OptionError("max_views", "must be >= min_views");
  if (max_frames < 1) throw OptionError("max_frames", "must be >= 1");
  if (!(min_view_change >= 0)) throw OptionError("min_view_change", "must be >= 0");
  if (!(max_rms_px > 0)) throw OptionError("max_rms_px", "must be positive");
  if (!(min_view_spread_deg >= 0 && min_view_spread_deg < 90))
    throw OptionError("min_view_spread_deg", "must be in [0, 90)");
  if (distortion_terms != 4 && distortion_terms != 5) throw OptionError("distortion_terms", "must be 4 or 5");
}

namespace {

// The largest angle between two views' board normals (the third column of each rotation).
double largestNormalAngleDeg(const std::vector<cv::Mat>& rvecs) {
  std::vector<cv::Vec3d> normals;
  for (const cv::Mat& rvec : rvecs) {
    cv::Matx33d R;
    cv::Rodrigues(rvec, R);
    normals.emplace_back(R(0, 2), R(1, 2), R(2, 2));
  }
  double smallest_cos = 1;
  for (size_t a = 0; a < normals.size(); ++a)
    for (size_t b = a + 1; b < normals.size(); ++b) smallest_cos = std::min(smallest_cos, normals[a].dot(normals[b]));
  return std::acos(std::max(-1.0, std::min(1.0, smallest_cos))) * 180.0 / M_PI;
}

}  // namespace

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

std::optional<CalibrationResult> SelfCalibrator::calibrate(std::string* why_not) {
  const auto refuse = [this, why_not](const std::string& why) {
    last_refusal_ = why;
    if (why_not) *why_not = why;
    return std::nullopt;
  };
  if (numViews() < options_.min_views)
    return refuse("calibration needs " + std::to_string(options_.min_views) + " views");
  std::vector<cv::Point3f> board;
  for (const Vec3& p : target_.cornersWorld())
    board.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()), 0.f);
  const std::vector<std::vector<cv::Point3f>> object(views_.size(), board);
  // Views that miss the image's corners leave the outer distortion unconstrained, k3 most of all:
  // a fit that folds there (measured: the phone video's 5-term fit, at 91 % of the way to its
  // corners) would undistort the corners' features onto wrong rays, so it is fitted again with k3,
  // then k2, fixed at 0.
  struct Model {
    int flags;
    const char* note;
  };
  const bool with_k3 = options_.distortion_terms == 5;
  std::vector<Model> models;
  if (with_k3) models.push_back({0, ""});
  models.push_back({cv::CALIB_FIX_K3, with_k3 ? "k3 fixed at 0: the distortion folds inside the image with it" : ""});
  models.push_back({cv::CALIB_FIX_K2 | cv::CALIB_FIX_K3, "k2 and k3 fixed at 0: the distortion folds inside the image with them"});
  std::string first_fold;
  for (const Model& model : models) {
    cv::Mat K, dist;
    std::vector<cv::Mat> rvecs, tvecs;
    const double rms = cv::calibrateCamera(object, views_, image_size_, K, dist, rvecs, tvecs, model.flags);
    if (!std::isfinite(rms) || rms > options_.max_rms_px)
      return refuse("their calibration's reprojection error, " + std::to_string(rms) + " px, is over max_rms_px " +
                    std::to_string(options_.max_rms_px) + (first_fold.empty() ? "" : " once it does not fold"));
    const double spread = largestNormalAngleDeg(rvecs);
    if (spread < options_.min_view_spread_deg)
      return refuse("the board faces the camera within " + formatString("%.1f", spread) +
                    " degrees of one orientation in all of them (min_view_spread_deg " +
                    formatString("%g", options_.min_view_spread_deg) +
                    "): parallel views do not determine the focal length; tilt the board between views");
    CalibrationResult result;
    result.camera = CameraModel::fromOpenCV(K, dist.reshape(1, 1).colRange(0, options_.distortion_terms), image_size_);
    const std::string fold = distortionFold(result.camera);
    if (fold.empty()) {
      result.rms_px = rms;
      result.views = numViews();
      result.note = model.note;
      return result;
    }
    if (first_fold.empty()) first_fold = fold;
  }
  return refuse("their calibration was not used, even with k2 and k3 fixed at 0: " + first_fold);
}

std::string SelfCalibrator::whyNotCalibrated() const {
  const std::string views = std::to_string(numViews()) + " distinct board views";
  const std::string failed = "no camera file, and self-calibration failed: ";
  if (!last_refusal_.empty()) return failed + views + ": " + last_refusal_ + "; give --camera";
  if (numViews() < options_.min_views)
    return failed + "only " + views + " (need " + std::to_string(options_.min_views) + "); give --camera";
  // Enough views, never tried: it waits for max_views views or max_frames frames.
  return "no camera file, and the run ended before self-calibrating: " + views + ", fewer than calibration.max_views (" +
         std::to_string(options_.max_views) + ") and the run shorter than calibration.max_frames (" +
         std::to_string(options_.max_frames) + " frames); lower calibration.max_frames, or give --camera";
}

CalibrationResult calibrateFromFrames(FrameSource& frames, const ChessboardTarget& target, cv::Size image_size,
                                      const SelfCalibrationOptions& options, const std::string& where,
                                      const ChessboardDetectorOptions& detector) {
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
    if (!detectChessboard(frame.grey, target, &uv, detector)) {
      if (!cv::findChessboardCornersSB(frame.grey, cv::Size(target.cols, target.rows), uv) ||
          static_cast<int>(uv.size()) != target.numCorners())
        continue;
      refineChessboardCorners(frame.grey, target, uv, detector);
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
  std::string why_not;
  const auto result = calibrator.calibrate(&why_not);
  if (!result)
    throw InputError(where, "the " + std::to_string(target.cols) + "x" + std::to_string(target.rows) +
                                " board was found in " + std::to_string(with_board) + " of " + std::to_string(done) +
                                " frames, giving " + std::to_string(calibrator.numViews()) + " distinct views; " +
                                why_not);
  return *result;
}

}  // namespace slamcmp
