#include "hybrid/board_corner_measurement.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/options.h"
#include "core/subpixel_corner.h"
#include "ekf/measurement_model.h"
#include "ekf/rolling_shutter.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

void BoardCornerMeasurementOptions::check() const {
  if (!(pixel_sigma > 0)) throw OptionError("pixel_sigma", "must be positive");
  if (!(gate > 0 && gate < 1)) throw OptionError("gate", "must be in (0, 1)");
  if (lk_window_px < 5 || lk_window_px % 2 == 0 || lk_window_px > 51)
    throw OptionError("lk_window_px", "must be odd and in [5, 51]");
  if (lk_levels < 0 || lk_levels > 6) throw OptionError("lk_levels", "must be in [0, 6]");
  if (!(max_track_disagreement_px > 0)) throw OptionError("max_track_disagreement_px", "must be positive");
  if (!(max_predicted_search >= 0 && max_predicted_search <= 0.5))
    throw OptionError("max_predicted_search", "must be in [0, 0.5] squares (a corner one square off must stay out)");
  if (!(max_plane_error_px > 0)) throw OptionError("max_plane_error_px", "must be positive");
  if (min_corners < 4) throw OptionError("min_corners", "must be >= 4 (a homography needs four)");
  if (!(min_corner_contrast >= 0 && min_corner_contrast <= 255))
    throw OptionError("min_corner_contrast", "must be in [0, 255] grey levels");
  if (search_interval < 1) throw OptionError("search_interval", "must be >= 1");
  if (!(reanchor_position_sigma >= 0 && reanchor_position_sigma < 10))
    throw OptionError("reanchor_position_sigma", "must be in [0, 10) m");
  if (!(reanchor_orientation_sigma >= 0 && reanchor_orientation_sigma < 1))
    throw OptionError("reanchor_orientation_sigma", "must be in [0, 1)");
  if (border_px < 0 || border_px > 100) throw OptionError("border_px", "must be in [0, 100]");
}

void BoardCornerMeasurementOptions::checkImage(cv::Size image) const {
  const int side = std::min(image.width, image.height);
  requireWithinImage("lk_window_px", lk_window_px, side, image);
  requireWithinImage("border_px", border_px, (side - 1) / 2, image);  // some image left inside the border
}

namespace {

constexpr double kMinCornerDepth = 0.05;  // m: a corner closer to the camera is not predicted

// The grey levels a corner's neighbourhood spans in this frame (`half` pixels either side): an
// X-junction's black and white squares span far more than the 16 asked (no corner of the renders'
// or vamr_checkerboard's falls under it: their trajectories are unchanged); a blank frame, none.
double cornerContrast(const cv::Mat& grey, const cv::Point2f& uv, int half) {
  const cv::Rect window = cv::Rect(cvRound(uv.x) - half, cvRound(uv.y) - half, 2 * half + 1, 2 * half + 1) &
                          cv::Rect(0, 0, grey.cols, grey.rows);
  if (window.empty()) return 0;
  double lo = 0, hi = 0;
  cv::minMaxLoc(grey(window), &lo, &hi);
  return hi - lo;
}

}  // namespace

BoardCornerMeasurer::BoardCornerMeasurer(const CameraModel& camera, const ChessboardTarget& target,
                                         const BoardCornerMeasurementOptions& options, double rolling_shutter_readout)
    : camera_(camera),
      target_(target),
      corners_world_(target.cornersWorld()),
      options_(options),
      readout_(rolling_shutter_readout),
      noise_(options.noise, options.pixel_sigma),
      exposure_(options.exposure),
      detector_(target, options.detector, options.presence) {}

void BoardCornerMeasurer::reset() {
  tracked_ids_.clear();
  tracked_uv_.clear();
}

void BoardCornerMeasurer::setMotionNoise(const MotionModelOptions& motion) {
  rolling_shutter_sigma_ = readout_ > 0 ? rollingShutterPixelSigma(camera_, readout_, motion) : 0.0;
}

double BoardCornerMeasurer::pixelSigma() const { return std::max(noise_.pixelSigma(), rolling_shutter_sigma_); }

std::vector<BoardCornerMeasurer::CornerPrediction> BoardCornerMeasurer::predict(const EkfState& state,
                                                                               const cv::Mat& grey) const {
  const int n = static_cast<int>(corners_world_.size());
  std::vector<CornerPrediction> pred(n);
  for (int i = 0; i < n; ++i) {
    CornerPrediction& p = pred[i];
    PointMeasurement next;  // the next corner along the row, for the square's size in pixels
    const Vec3 along = corners_world_[i] + Vec3(target_.square_size, 0, 0);
    if (!predictAtRowTime(camera_, readout_, state.x().head<13>(), corners_world_[i], &p.h, kMinCornerDepth) ||
        !predictAtRowTime(camera_, readout_, state.x().head<13>(), along, &next, kMinCornerDepth))
      continue;
    const Vec2& uv = p.h.uv_distorted;
    p.square_px = (next.uv_distorted - uv).norm();
    // The refinement's window must stay inside the image: a window cut by the border biases the
    // corner by pixels.
    const double border = std::max<double>(options_.border_px, refineHalfWindow(p.square_px) + 2);
    p.in_image = uv.x() >= border && uv.y() >= border && uv.x() <= grey.cols - 1 - border &&
                 uv.y() <= grey.rows - 1 - border;
    if (!p.in_image) continue;
    p.S = pointInnovationCovariance(state, p.h, kKnownPoint, pixelSigma()) + exposure_.covariance();
    p.half_axis_px = 3.0 * largestStd(p.S);
  }
  return pred;
}

BoardCornerMeasurement BoardCornerMeasurer::measureDetected(const EkfState& state, const cv::Mat& grey,
                                                            const std::vector<cv::Point2f>& uv_distorted) {
  const std::vector<CornerPrediction> pred = predict(state, grey);
  std::vector<int> ids(uv_distorted.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
  std::vector<cv::Mat> pyramid;
  cv::buildOpticalFlowPyramid(grey, pyramid, cv::Size(options_.lk_window_px, options_.lk_window_px),
                              options_.lk_levels);
  BoardCornerMeasurement out = keep(pred, ids, uv_distorted);
  pyramid_prev_ = std::move(pyramid);
  return out;
}

std::vector<int> spotCheckCorners(const std::vector<int>& ids, int cols) {
  if (ids.empty()) return {};
  // Extreme in a i + b j for (a, b) = (1, 0), (0, 1), (1, 1), (1, -1), either way: the hull's
  // vertices, where an affine function over the tracked part of the board (the start error of a
  // pose error, nearly) is largest.
  constexpr int kDirections[4][2] = {{1, 0}, {0, 1}, {1, 1}, {1, -1}};
  std::vector<int> spot;
  for (const auto& d : kDirections) {
    const auto along = [&](int id) { return d[0] * (id % cols) + d[1] * (id / cols); };
    const auto [lo, hi] = std::minmax_element(ids.begin(), ids.end(), [&](int a, int b) { return along(a) < along(b); });
    for (const int id : {*lo, *hi})
      if (std::find(spot.begin(), spot.end(), id) == spot.end()) spot.push_back(id);
  }
  return spot;
}

void BoardCornerMeasurer::trackCorners(const std::vector<CornerPrediction>& pred, const std::vector<cv::Mat>& pyramid,
                                       std::vector<int>* ids, std::vector<cv::Point2f>* uv) const {
  // The corners tracked into the last frame that this one's prediction keeps in the image.
  std::vector<int> track_ids;
  std::vector<cv::Point2f> previous, from_prediction;
  for (size_t k = 0; k < tracked_ids_.size(); ++k) {
    const CornerPrediction& p = pred[tracked_ids_[k]];
    if (!p.in_image) continue;
    track_ids.push_back(tracked_ids_[k]);
    previous.push_back(tracked_uv_[k]);
    from_prediction.emplace_back(static_cast<float>(p.h.uv_distorted.x()), static_cast<float>(p.h.uv_distorted.y()));
  }
  // Tracked from the previous frame, started where the filter predicts each corner (its
  // constant-velocity motion: a fast turn moves the board by most of a square a frame).
  // Lucas-Kanade started more than half a square off settles on a neighbour that looks alike (the
  // diagonal one), every corner alike, which neither the gate nor the board's plane can tell:
  // corners are also tracked from where they were, and the two starts agree only on the right
  // one. A bad start comes from a pose error, which moves the starts about affinely over the
  // board: the corners on the hull of those tracked (spotCheckCorners) are checked first, and
  // the others only if one of those disagrees (a lone corner on its neighbour leaves the board's
  // plane, where the plane test drops it).
  if (track_ids.empty() || pyramid_prev_.empty()) return;
  const cv::Size lk_window(options_.lk_window_px, options_.lk_window_px);
  std::vector<unsigned char> tracked;
  const cv::TermCriteria lk_stop(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 30, 0.01);
  cv::calcOpticalFlowPyrLK(pyramid_prev_, pyramid, previous, from_prediction, tracked, cv::noArray(), lk_window,
                           options_.lk_levels, lk_stop, cv::OPTFLOW_USE_INITIAL_FLOW);
  // Tracks corners `which` (indices into track_ids) from where they were too, and clears
  // `tracked` for those whose two starts disagree; false when one of them does.
  const auto check = [&](const std::vector<size_t>& which) {
    std::vector<cv::Point2f> from, from_previous;
    for (size_t k : which) from.push_back(previous[k]);
    std::vector<unsigned char> tracked_previous;
    cv::calcOpticalFlowPyrLK(pyramid_prev_, pyramid, from, from_previous, tracked_previous, cv::noArray(),
                             lk_window, options_.lk_levels, lk_stop);
    bool all_agree = true;
    for (size_t j = 0; j < which.size(); ++j) {
      const size_t k = which[j];
      const bool agree = tracked[k] && tracked_previous[j] &&
                         cv::norm(from_prediction[k] - from_previous[j]) <= options_.max_track_disagreement_px;
      tracked[k] = agree;
      all_agree = all_agree && agree;
    }
    return all_agree;
  };
  const std::vector<int> spot_ids = spotCheckCorners(track_ids, target_.cols);
  std::vector<size_t> spot, rest;
  for (size_t k = 0; k < track_ids.size(); ++k)
    (std::find(spot_ids.begin(), spot_ids.end(), track_ids[k]) != spot_ids.end() ? spot : rest).push_back(k);
  if (!check(spot) && !rest.empty()) check(rest);
  for (size_t k = 0; k < track_ids.size(); ++k) {
    if (!tracked[k]) continue;
    ids->push_back(track_ids[k]);
    uv->push_back(from_prediction[k]);
  }
}

void BoardCornerMeasurer::refineCandidates(const std::vector<CornerPrediction>& pred, const cv::Mat& grey, int half,
                                           std::vector<int>* ids, std::vector<cv::Point2f>* uv) const {
  // The others refined where the filter predicts them, when its uncertainty is well under a square.
  for (int i = 0; i < static_cast<int>(pred.size()); ++i) {
    if (!pred[i].in_image || std::find(ids->begin(), ids->end(), i) != ids->end()) continue;
    if (pred[i].half_axis_px > options_.max_predicted_search * pred[i].square_px) continue;
    ids->push_back(i);
    uv->emplace_back(static_cast<float>(pred[i].h.uv_distorted.x()), static_cast<float>(pred[i].h.uv_distorted.y()));
  }
  refineCornersSubpixel(grey, half, *uv, options_.detector.subpixel, &camera_);
  // Tracking and refinement both leave a corner where it started on a blank frame (LK's gradients
  // are the last frame's; a flat window moves no refinement), and the corners were measured at
  // their predictions, posing a frame that showed nothing.
  size_t contrasted = 0;
  for (size_t k = 0; k < ids->size(); ++k)
    if (cornerContrast(grey, (*uv)[k], half) >= options_.min_corner_contrast) {
      (*ids)[contrasted] = (*ids)[k];
      (*uv)[contrasted++] = (*uv)[k];
    }
  ids->resize(contrasted);
  uv->resize(contrasted);
}

BoardCornerMeasurement BoardCornerMeasurer::measure(const EkfState& state, const cv::Mat& grey) {
  const int n = static_cast<int>(corners_world_.size());
  const std::vector<CornerPrediction> pred = predict(state, grey);
  int predicted = 0;
  std::vector<double> squares;
  for (const CornerPrediction& p : pred)
    if (p.in_image) {
      ++predicted;
      squares.push_back(p.square_px);
    }
  const bool all_in_image = predicted == n;
  outside_gates_.clear();
  std::vector<cv::Mat> pyramid;
  const cv::Size lk_window(options_.lk_window_px, options_.lk_window_px);
  cv::buildOpticalFlowPyramid(grey, pyramid, lk_window, options_.lk_levels);
  if (predicted == 0) {
    reset();
    pyramid_prev_ = std::move(pyramid);
    return {};
  }
  std::nth_element(squares.begin(), squares.begin() + squares.size() / 2, squares.end());
  const double square_px = squares[squares.size() / 2];
  const int half = refineHalfWindow(square_px);

  // The board back in view with no corner tracked from the last frame: found by the detector where
  // the filter predicts it, which orders the corners by the board itself. Refined at a prediction a
  // square off, every corner settles on its neighbour, a whole grid the plane test and the gates of
  // a filter unsure after the gap take for the board (vamr, frame 221: 40 mm off for 500 frames).
  const bool search_first = tracked_ids_.empty() && all_in_image;
  std::optional<BoardCornerMeasurement> found;
  if (search_first) found = searchPredicted(pred, grey, square_px);
  BoardCornerMeasurement out;
  if (found) {
    out = std::move(*found);
  } else {
    std::vector<int> ids;
    std::vector<cv::Point2f> uv;
    trackCorners(pred, pyramid, &ids, &uv);
    refineCandidates(pred, grey, half, &ids, &uv);
    out = keep(pred, ids, uv);
    // Most of the corners lost by the tracking: a board search where the filter predicts it.
    if (!search_first && static_cast<int>(out.observations.size()) * 2 < predicted && all_in_image)
      if (auto board = searchPredicted(pred, grey, square_px)) out = std::move(*board);
  }
  pyramid_prev_ = std::move(pyramid);
  if (static_cast<int>(tracked_ids_.size()) == n) {  // the whole board: what the presence test learns from
    std::vector<cv::Point2f> whole(n);
    for (size_t k = 0; k < tracked_ids_.size(); ++k) whole[tracked_ids_[k]] = tracked_uv_[k];
    detector_.seen(grey, whole);
  }
  return out;
}

std::vector<cv::Point2f> BoardCornerMeasurer::searchWholeImage(const cv::Mat& grey) {
  std::vector<cv::Point2f> found;
  if (!detector_.detect(grey, &found)) return {};
  return found;
}

std::vector<cv::Point2f> BoardCornerMeasurer::searchPredictedRegion(const std::vector<CornerPrediction>& pred,
                                                                    const cv::Mat& grey, double square_px) {
  const int n = static_cast<int>(pred.size());
  double half_axis = 0;
  Vec2 lo = Vec2::Constant(1e9), hi = Vec2::Constant(-1e9);
  std::vector<cv::Point2f> predicted_uv(n);
  for (int i = 0; i < n; ++i) {
    const Vec2& uv = pred[i].h.uv_distorted;
    predicted_uv[i] = cv::Point2f(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
    lo = lo.cwiseMin(uv);
    hi = hi.cwiseMax(uv);
    half_axis = std::max(half_axis, pred[i].half_axis_px);
  }
  // The detector needs the outer squares and the white margin around them: 2.5 squares.
  const double margin = std::max(half_axis, 2.5 * square_px);
  const cv::Rect roi = cv::Rect(cv::Point(static_cast<int>(lo.x() - margin), static_cast<int>(lo.y() - margin)),
                                cv::Point(static_cast<int>(hi.x() + margin) + 1, static_cast<int>(hi.y() + margin) + 1)) &
                       cv::Rect(0, 0, grey.cols, grey.rows);
  std::vector<cv::Point2f> found;
  if (roi.area() == 0 || !detector_.detect(grey, roi, &found)) return {};
  chooseSymmetricOrder(target_, found, predicted_uv);  // a symmetric board: the predicted origin
  return found;
}

std::optional<BoardCornerMeasurement> BoardCornerMeasurer::searchPredicted(const std::vector<CornerPrediction>& pred,
                                                                          const cv::Mat& grey, double square_px) {
  const std::vector<cv::Point2f> found = searchPredictedRegion(pred, grey, square_px);
  if (found.empty()) return std::nullopt;
  std::vector<int> ids(pred.size());
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<int>(i);
  BoardCornerMeasurement kept = keep(pred, ids, found);
  if (kept.observations.size() >= kMinFoundCornersFitting * found.size()) return kept;
  reset();
  outside_gates_ = found;
  return BoardCornerMeasurement();
}

BoardCornerMeasurement BoardCornerMeasurer::measureNew(const EkfState& state, const cv::Mat& grey) {
  if (tracked_ids_.empty()) return {};
  const std::vector<CornerPrediction> pred = predict(state, grey);
  std::vector<int> ids;
  std::vector<cv::Point2f> uv;
  std::vector<double> squares;
  for (int i = 0; i < static_cast<int>(pred.size()); ++i) {
    const CornerPrediction& p = pred[i];
    if (!p.in_image || std::find(tracked_ids_.begin(), tracked_ids_.end(), i) != tracked_ids_.end() ||
        p.half_axis_px > options_.max_predicted_search * p.square_px)
      continue;
    ids.push_back(i);
    uv.emplace_back(static_cast<float>(p.h.uv_distorted.x()), static_cast<float>(p.h.uv_distorted.y()));
    squares.push_back(p.square_px);
  }
  if (ids.empty()) return {};
  std::nth_element(squares.begin(), squares.begin() + squares.size() / 2, squares.end());
  refineCornersSubpixel(grey, refineHalfWindow(squares[squares.size() / 2]), uv, options_.detector.subpixel,
                        &camera_);
  // Gated one by one, then on the board plane with the corners already kept this frame.
  std::vector<int> all_ids = tracked_ids_;
  std::vector<Vec2> all_z;
  for (const cv::Point2f& p : tracked_uv_) all_z.emplace_back(p.x, p.y);
  const size_t first_new = all_ids.size();
  for (size_t k = 0; k < ids.size(); ++k) {
    const Vec2 measured(uv[k].x, uv[k].y);
    if (!withinGate(pred[ids[k]], measured)) continue;
    all_ids.push_back(ids[k]);
    all_z.push_back(measured);
  }
  const std::vector<double> errors = planeErrorsPx(all_ids, all_z);
  BoardCornerMeasurement out;
  for (size_t k = first_new; k < all_ids.size(); ++k) {
    if (errors[k] <= options_.max_plane_error_px) use(all_ids[k], all_z[k], pred[all_ids[k]].h, &out);
  }
  return out;
}

bool BoardCornerMeasurer::update(EkfState& state, BoardCornerMeasurement* m) {
  const Relinearise predict_at = [&](const Eigen::VectorXd& x, std::vector<PointObservation>* observations) {
    for (size_t k = 0; k < observations->size(); ++k)
      if (!predictAtRowTime(camera_, readout_, x.head<13>(), corners_world_[m->corner_ids[k]], &(*observations)[k].h,
                            kMinCornerDepth))
        return false;
    return true;
  };
  // Counted again as a new shift, the frame's one would give the filter its information twice.
  constexpr double kSpent = 1e6;
  const Mat2 shared = shift_spent_ ? kSpent * exposure_.covariance() : exposure_.covariance();
  shift_spent_ = shift_spent_ || !shared.isZero(0);
  return iteratedUpdate(state, &m->observations, PointNoise(pixelSigma(), shared), predict_at);
}

void BoardCornerMeasurer::use(int id, const Vec2& z, const PointMeasurement& h, BoardCornerMeasurement* out) {
  PointObservation o;
  o.offset = kKnownPoint;
  o.z = z;
  o.h = h;
  out->observations.push_back(o);
  out->corner_ids.push_back(id);
  tracked_ids_.push_back(id);
  tracked_uv_.emplace_back(static_cast<float>(z.x()), static_cast<float>(z.y()));
}

bool BoardCornerMeasurer::withinGate(const CornerPrediction& p, const Vec2& measured) const {
  const double gate = -2.0 * std::log(1.0 - options_.gate);  // chi-square quantile, 2 dof
  const Vec2 nu = measured - p.h.uv_distorted;
  return measured.allFinite() && nu.dot(p.S.ldlt().solve(nu)) <= gate;
}

int BoardCornerMeasurer::refineHalfWindow(double square_px) const {
  // Half side 0.4 square: a window 0.8 square across, inside the four squares meeting at the corner,
  // twice the detector's (`detector.refine_window_fraction` is its side, under SPEC section 6's half
  // square, and this does not read it): hybrid's measured figures are with this one. Compared as a
  // double: a diverged filter's square can be huge or NaN, beyond int.
  const double half = 0.4 * square_px;
  if (!(half < options_.detector.max_refine_half_window)) return options_.detector.max_refine_half_window;
  return std::max(2, static_cast<int>(half));
}

std::vector<double> BoardCornerMeasurer::planeErrorsPx(const std::vector<int>& ids, const std::vector<Vec2>& z) const {
  std::vector<Vec2> plane, xy;
  for (size_t k = 0; k < ids.size(); ++k) {
    plane.push_back(corners_world_[ids[k]].head<2>());
    xy.push_back(camera_.undistortPixel(z[k]));
  }
  std::vector<double> errors = homographyErrors(homographyDlt(plane, xy), plane, xy);
  const double focal = 0.5 * (camera_.fx + camera_.fy);
  for (double& e : errors) e *= focal;
  return errors;
}

BoardCornerMeasurement BoardCornerMeasurer::keep(const std::vector<CornerPrediction>& pred, const std::vector<int>& ids,
                                                 const std::vector<cv::Point2f>& uv) {
  BoardCornerMeasurement out;
  // Each corner within its own innovation gate.
  std::vector<int> kept;
  std::vector<Vec2> z;
  for (size_t k = 0; k < ids.size(); ++k) {
    const Vec2 measured(uv[k].x, uv[k].y);
    if (!pred[ids[k]].in_image || !withinGate(pred[ids[k]], measured)) continue;
    kept.push_back(ids[k]);
    z.push_back(measured);
  }
  // The set on the board plane: a homography through the kept corners; the ones off it are dropped
  // (twice: the first fit may be pulled by the worst; a fit that drops none is the last).
  std::vector<double> errors;
  bool fits_kept = false;  // `errors` are those of a fit through exactly the kept corners
  for (int pass = 0; pass < 2 && !fits_kept && static_cast<int>(kept.size()) >= options_.min_corners; ++pass) {
    errors = planeErrorsPx(kept, z);
    std::vector<int> kept_next;
    std::vector<Vec2> z_next;
    for (size_t k = 0; k < kept.size(); ++k)
      if (errors[k] <= options_.max_plane_error_px) {
        kept_next.push_back(kept[k]);
        z_next.push_back(z[k]);
      }
    fits_kept = kept_next.size() == kept.size();
    kept.swap(kept_next);
    z.swap(z_next);
  }
  reset();
  if (static_cast<int>(kept.size()) >= options_.min_corners) {
    if (options_.noise.enabled) noise_.add(fits_kept ? errors : planeErrorsPx(kept, z));
    for (size_t k = 0; k < kept.size(); ++k) use(kept[k], z[k], pred[kept[k]].h, &out);
  }
  return out;
}

}  // namespace slamcmp
