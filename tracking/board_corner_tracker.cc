#include "tracking/board_corner_tracker.h"

#include <algorithm>
#include <cmath>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "core/error.h"
#include "core/statistics.h"
#include "core/subpixel_corner.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

void BoardCornerTrackerOptions::check() const {
  if (!(max_grid_error_px > 0)) throw OptionError("max_grid_error_px", "must be positive");
  if (!(max_refine_shift_px > 0)) throw OptionError("max_refine_shift_px", "must be positive");
  if (!(max_corner_error_px > 0)) throw OptionError("max_corner_error_px", "must be positive");
  if (search_margin_px < 0) throw OptionError("search_margin_px", "must be >= 0");
  if (search_interval_when_lost < 1) throw OptionError("search_interval_when_lost", "must be >= 1");
  if (search_interval_when_predicted < 1) throw OptionError("search_interval_when_predicted", "must be >= 1");
  if (!(region_margin_px >= 0)) throw OptionError("region_margin_px", "must be >= 0");
  if (min_partial_corners != 0 && min_partial_corners < 6)
    throw OptionError("min_partial_corners", "must be 0 (whole boards only) or >= 6");
  if (!(max_prediction_error_px >= 1)) throw OptionError("max_prediction_error_px", "must be >= 1");
  if (!(min_square_contrast > 0)) throw OptionError("min_square_contrast", "must be positive");
}

namespace {

// Mean grey level of the 3x3 pixels at grid coordinates `grid` (H maps the grid to undistorted
// pixels, its sign as homographyDlt's), or -1 outside the image.
double sampleGrid(const cv::Mat& grey, const CameraModel& camera, const Mat3& H, const Vec2& grid) {
  const Vec3 u = H * grid.homogeneous();
  if (!(u.z() > 0)) return -1;  // beyond the plane's horizon
  const Vec2 uv = camera.project(camera.normalisedFromPixel(u.hnormalized()).homogeneous());
  if (!uv.allFinite() || !camera.inImage(uv, 2)) return -1;
  const int x = static_cast<int>(std::lround(uv.x())), y = static_cast<int>(std::lround(uv.y()));
  double sum = 0;
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) sum += grey.at<uchar>(y + dy, x + dx);
  return sum / 9;
}

// A corner is dropped when the grid's homography misses it by more than max_corner_error_px and
// by more than this many times the median corner.
constexpr double kMaxCornerErrorOverMedian = 3.0;
// A corner's four squares are sampled this far from it along the grid (squares): inside the
// sub-pixel window (under half a square wide), where an occluding edge would pull the refinement.
constexpr double kSquareSampleOffset = 0.3;
// A side of a partial board whose squares seem to go on beyond its outer squares (more than this
// fraction of at least this many samples) is a board slipped by two squares; so is one whose
// corners stop short of its edge where the squares beyond them, in view, seem not to go on (this
// fraction or less).
constexpr double kMaxContinuingFraction = 0.8;
constexpr int kMinEdgeSamples = 4;

const cv::TermCriteria kCoarseLk(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 10, 0.1);

Vec2 gridOf(const ChessboardTarget& t, int id) { return Vec2(id % t.cols, id / t.cols); }

// subsetSpacing's answer when no two corners are next to each other on the grid.
constexpr double kUnknownSpacing = 1e30;

// Smallest distance between two corners of `c` that are neighbours on the grid, pixels.
double subsetSpacing(const ChessboardTarget& t, const BoardCorners& c) {
  std::vector<int> at(t.numCorners(), -1);
  for (size_t k = 0; k < c.ids.size(); ++k) at[c.ids[k]] = static_cast<int>(k);
  double best = kUnknownSpacing;
  for (size_t k = 0; k < c.ids.size(); ++k) {
    const int i = c.ids[k] % t.cols, j = c.ids[k] / t.cols;
    if (i + 1 < t.cols && at[c.ids[k] + 1] >= 0) best = std::min<double>(best, cv::norm(c.uv[at[c.ids[k] + 1]] - c.uv[k]));
    if (j + 1 < t.rows && at[c.ids[k] + t.cols] >= 0)
      best = std::min<double>(best, cv::norm(c.uv[at[c.ids[k] + t.cols]] - c.uv[k]));
  }
  return best;
}

// The sub-pixel window's half side for corners `spacing` pixels apart: as core's
// refineChessboardCorners (a window under refine_window_fraction of a square). Corners none of
// which are next to each other (kUnknownSpacing, which made an int was undefined) get the smallest
// window.
int refineHalfWindow(double spacing, const ChessboardDetectorOptions& options) {
  if (!(spacing < kUnknownSpacing)) return 1;
  return std::clamp(static_cast<int>((options.refine_window_fraction * spacing - 1) / 2), 1,
                    options.max_refine_half_window);
}

}  // namespace

BoardCornerTracker::BoardCornerTracker(const ChessboardTarget& target, const BoardCornerTrackerOptions& options)
    : target_(target), options_(options), detector_(target, options.detector, options.presence) {}

void BoardCornerTracker::rememberWholeBoard(const cv::Mat& grey, const std::vector<cv::Point2f>& uv) {
  last_seen_ = uv;
  detector_.seen(grey, uv);
}

bool BoardCornerTracker::fullSearchDue(bool allow_search, bool predicted) {
  // Frames are counted whether or not a search was allowed: the first frame allowed after a
  // stretch searches at once.
  const int interval = predicted ? options_.search_interval_when_predicted : options_.search_interval_when_lost;
  frames_since_search_ = std::min(frames_since_search_ + 1, kNeverSearched);
  if (!allow_search || frames_since_search_ < interval) return false;
  frames_since_search_ = 0;
  last_searched_whole_ = true;
  return true;
}

cv::Rect BoardCornerTracker::predictedRegion(const cv::Mat& grey, const std::vector<cv::Point2f>& expected) const {
  if (static_cast<int>(expected.size()) != target_.numCorners()) return {};
  for (const cv::Point2f& p : expected)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) return {};
  float x0 = expected[0].x, y0 = expected[0].y, x1 = x0, y1 = y0;
  for (const cv::Point2f& p : expected) x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
  const cv::Rect2f box(x0, y0, x1 - x0, y1 - y0);
  const cv::Rect2f image(0, 0, static_cast<float>(grey.cols), static_cast<float>(grey.rows));
  const auto grown = [](const cv::Rect2f& r, double by) {
    const auto b = static_cast<float>(by);
    return cv::Rect2f(r.x - b, r.y - b, r.width + 2 * b, r.height + 2 * b);
  };
  // The board may be wholly in view only if its predicted corners are, give or take the
  // prediction's error.
  if ((box & grown(image, options_.region_margin_px)) != box) return {};
  BoardCorners all;
  all.uv = expected;
  for (int id = 0; id < target_.numCorners(); ++id) all.ids.push_back(id);
  // The detector needs the outer squares (a square beyond the inner corners) and their margin.
  const cv::Rect2f region = grown(box, options_.region_margin_px + subsetSpacing(target_, all)) & image;
  return cv::Rect(cv::Point(static_cast<int>(std::floor(region.x)), static_cast<int>(std::floor(region.y))),
                  cv::Point(static_cast<int>(std::ceil(region.br().x)), static_cast<int>(std::ceil(region.br().y)))) &
         cv::Rect(0, 0, grey.cols, grey.rows);
}

int BoardCornerTracker::minCorners() const {
  return options_.min_partial_corners > 0 ? std::min(options_.min_partial_corners, target_.numCorners())
                                          : target_.numCorners();
}

double BoardCornerTracker::refineMarginPx(const BoardCorners& corners) const {
  const double spacing = subsetSpacing(target_, corners);
  return spacing < kUnknownSpacing ? refineHalfWindow(spacing, options_.detector) + 2.0 : 2.0;
}

std::optional<std::pair<double, double>> BoardCornerTracker::squareMeans(const cv::Mat& grey,
                                                                         const BoardCorners& c) const {
  if (c.ids.size() < 4) return std::nullopt;
  std::vector<int> at(target_.numCorners(), -1);
  for (size_t k = 0; k < c.ids.size(); ++k) at[c.ids[k]] = static_cast<int>(k);
  // The squares are sampled at whole pixels: the direct linear fit places them well enough
  // (cv::findHomography's geometric refinement after it cost 0.12 ms a frame).
  std::vector<Vec2> grid, uv;
  for (size_t k = 0; k < c.ids.size(); ++k) {
    grid.push_back(gridOf(target_, c.ids[k]));
    uv.emplace_back(c.uv[k].x, c.uv[k].y);
  }
  const Mat3 H = homographyDlt(grid, uv);
  // The square diagonally outside corner 0, centred at (-0.5, -0.5), is black (SPEC section 2), so
  // the square centred at (i + 0.5, j + 0.5) is black when i + j is even. Only squares whose four
  // corners were found are sampled (they are in the image).
  double sum[2] = {0, 0};
  int n[2] = {0, 0};
  for (int j = 0; j + 1 < target_.rows; ++j)
    for (int i = 0; i + 1 < target_.cols; ++i) {
      const int id = j * target_.cols + i;
      if (at[id] < 0 || at[id + 1] < 0 || at[id + target_.cols] < 0 || at[id + target_.cols + 1] < 0) continue;
      const int white = (i + j) % 2;
      for (double di : {-0.2, 0.0, 0.2})
        for (double dj : {-0.2, 0.0, 0.2}) {
          const Vec2 p = (H * Vec3(i + 0.5 + di, j + 0.5 + dj, 1.0)).hnormalized();
          const int u = static_cast<int>(std::lround(p.x()));
          const int v = static_cast<int>(std::lround(p.y()));
          if (u < 0 || v < 0 || u >= grey.cols || v >= grey.rows) continue;
          sum[white] += grey.at<uchar>(v, u);
          ++n[white];
        }
    }
  if (!n[0] || !n[1]) return std::nullopt;
  // (black, white) as SPEC section 2 numbers the squares; parity_ turns them for a symmetric board
  // numbered the other way round.
  const double even = sum[0] / n[0], odd = sum[1] / n[1];
  return parity_ > 0 ? std::make_pair(even, odd) : std::make_pair(odd, even);
}

double BoardCornerTracker::squareContrast(const cv::Mat& grey, const BoardCorners& c) const {
  const auto means = squareMeans(grey, c);
  return means ? means->second - means->first : 0.0;
}

bool BoardCornerTracker::confirmCorners(const cv::Mat& grey, BoardCorners* c, const CameraModel& camera) const {
  if (static_cast<int>(c->ids.size()) < minCorners()) return false;
  const std::vector<cv::Point2f> start = c->uv;
  const int half = refineHalfWindow(subsetSpacing(target_, *c), options_.detector);
  refineCornersSubpixel(grey, half, c->uv, options_.detector.subpixel, &camera);
  // A corner the refinement moves far was not where tracking or the prediction put it (or is no
  // longer a corner): it is dropped, the rest stand.
  BoardCorners kept;
  for (size_t k = 0; k < c->ids.size(); ++k) {
    const Vec2 uv(c->uv[k].x, c->uv[k].y);
    if (cv::norm(c->uv[k] - start[k]) > options_.max_refine_shift_px || !camera.inImage(uv, half)) continue;
    kept.ids.push_back(c->ids[k]);
    kept.uv.push_back(c->uv[k]);
  }
  if (static_cast<int>(kept.ids.size()) < minCorners()) return false;
  // The grid must still be a plane seen through the lens: a homography from the board to the
  // undistorted corners fits them all. The corners it does not fit (one beside the edge of something
  // hiding part of the board: the refinement is pulled off the corner) are dropped, all at once.
  std::vector<Vec2> plane, undistorted;
  for (size_t k = 0; k < kept.ids.size(); ++k) {
    plane.push_back(gridOf(target_, kept.ids[k]));
    undistorted.push_back(camera.undistortToPixel(Vec2(kept.uv[k].x, kept.uv[k].y)));
  }
  if (!determinesAHomography(plane)) return false;  // e.g. one row of the board: no homography, no pose
  // Each corner's four squares, sampled near it (within the refinement's window), must show
  // their colours: a corner beside the edge of something hiding part of the board has the
  // refinement pulled off it.
  Mat3 H = homographyDlt(plane, undistorted);
  bool h_fits_kept = true;  // H is still the least-squares fit of every kept corner
  {
    BoardCorners clear;
    std::vector<Vec2> clear_plane, clear_undistorted;
    for (size_t k = 0; k < kept.ids.size(); ++k) {
      if (!squaresClear(grey, camera, H, plane[k])) continue;
      clear.ids.push_back(kept.ids[k]);
      clear.uv.push_back(kept.uv[k]);
      clear_plane.push_back(plane[k]);
      clear_undistorted.push_back(undistorted[k]);
    }
    if (static_cast<int>(clear.ids.size()) < minCorners()) return false;
    h_fits_kept = clear.ids.size() == kept.ids.size();
    kept = std::move(clear);
    plane = std::move(clear_plane);
    undistorted = std::move(clear_undistorted);
  }
  // The corners the grid's homography does not fit are dropped: the homography from the corners
  // RANSAC at max_corner_error_px keeps (least squares on them), or from them all where it would
  // keep them all; the limit that, or a few times the median corner's error from it, whichever is
  // larger (real corners are noisier: a blurred phone video's miss by 0.3 to 0.5 px; a rendered
  // board's by 0.05 px, and one beside an occluding edge by 1 to 3 px).
  // The whole board's least-squares fit stands for RANSAC's (0.16 ms a frame) where it fits every
  // corner within both limits. A fit that includes a stray corner hides it only where the corners
  // are few (a review's simulation, 0.05 px noise and one corner 0.6 px off: missed 277 and 96
  // times in 400 among 8 and 12 corners, never among 54), so a partial board always goes through
  // RANSAC. On vamr's blurred corners RANSAC's consensus, a fit to part of the board, had dropped
  // up to 13 corners of a whole view that the whole fit keeps.
  std::vector<double> errors;
  if (static_cast<int>(plane.size()) == target_.numCorners())
    errors = homographyErrors(h_fits_kept ? H : homographyDlt(plane, undistorted), plane, undistorted);
  if (errors.empty() || !(*std::max_element(errors.begin(), errors.end()) <=
                          std::min(options_.max_corner_error_px, kMaxCornerErrorOverMedian * median(errors)))) {
    std::vector<cv::Point2f> plane_cv, undistorted_cv;
    for (size_t k = 0; k < plane.size(); ++k) {
      plane_cv.emplace_back(static_cast<float>(plane[k].x()), static_cast<float>(plane[k].y()));
      undistorted_cv.emplace_back(static_cast<float>(undistorted[k].x()), static_cast<float>(undistorted[k].y()));
    }
    std::vector<uchar> inlier;
    if (cv::findHomography(plane_cv, undistorted_cv, cv::RANSAC, options_.max_corner_error_px, inlier).empty())
      return false;
    std::vector<Vec2> inlier_plane, inlier_undistorted;
    for (size_t k = 0; k < plane.size(); ++k)
      if (inlier[k]) inlier_plane.push_back(plane[k]), inlier_undistorted.push_back(undistorted[k]);
    if (inlier_plane.size() < 4) return false;
    errors = homographyErrors(homographyDlt(inlier_plane, inlier_undistorted), plane, undistorted);
  }
  const double limit = std::max(options_.max_corner_error_px, kMaxCornerErrorOverMedian * median(errors));
  {
    BoardCorners fitting;
    std::vector<Vec2> fitting_plane, fitting_undistorted;
    std::vector<double> fitting_errors;
    for (size_t k = 0; k < errors.size(); ++k) {
      if (errors[k] > limit) continue;
      fitting.ids.push_back(kept.ids[k]);
      fitting.uv.push_back(kept.uv[k]);
      fitting_plane.push_back(plane[k]);
      fitting_undistorted.push_back(undistorted[k]);
      fitting_errors.push_back(errors[k]);
    }
    if (static_cast<int>(fitting.ids.size()) < minCorners()) return false;
    kept = std::move(fitting);
    plane = std::move(fitting_plane);
    undistorted = std::move(fitting_undistorted);
    errors = std::move(fitting_errors);
  }
  if (!determinesAHomography(plane)) return false;  // corners dropped down to one row, or near it
  kept.complete = static_cast<int>(kept.ids.size()) == target_.numCorners();
  double sum = 0;
  for (double e : errors) sum += e * e;
  if (std::sqrt(sum / static_cast<double>(kept.ids.size())) > options_.max_grid_error_px) return false;
  // A slip of the grid by one square keeps it consistent but swaps the squares' colours.
  if (squareContrast(grey, kept) < options_.min_square_contrast) return false;
  // A slip by two squares keeps the colours too: part of a board must end where its edges say.
  if (!kept.complete && !endsAtItsEdges(grey, camera, homographyDlt(plane, undistorted), kept)) return false;
  *c = std::move(kept);
  return true;
}

bool BoardCornerTracker::squaresClear(const cv::Mat& grey, const CameraModel& camera, const Mat3& H,
                                      const Vec2& grid) const {
  const auto sample = [&](const Vec2& g) { return sampleGrid(grey, camera, H, g); };
  // The square at (i - 0.5, j - 0.5) is black when i + j is even (SPEC section 2); parity_
  // turns this for a symmetric board numbered the other way round.
  const int i = static_cast<int>(grid.x()), j = static_cast<int>(grid.y());
  const bool first_black = ((i + j) % 2 == 0) == (parity_ > 0);
  double darkest_white = 1e9, brightest_black = -1e9;
  for (const double di : {-kSquareSampleOffset, kSquareSampleOffset})
    for (const double dj : {-kSquareSampleOffset, kSquareSampleOffset}) {
      const double v = sample(grid + Vec2(di, dj));
      if (v < 0) return false;
      const bool black = (di < 0) == (dj < 0) ? first_black : !first_black;
      if (black) brightest_black = std::max(brightest_black, v);
      else darkest_white = std::min(darkest_white, v);
    }
  return darkest_white - brightest_black >= options_.min_square_contrast;
}

bool BoardCornerTracker::endsAtItsEdges(const cv::Mat& grey, const CameraModel& camera, const Mat3& H,
                                        const BoardCorners& c) const {
  const auto means = squareMeans(grey, c);
  if (!means) return false;
  // Sides -x, +x, -y, +y: the kept corners' outermost grid line on each, and the board's edge.
  const Vec2 outwards[4] = {Vec2(-1, 0), Vec2(1, 0), Vec2(0, -1), Vec2(0, 1)};
  const int edge[4] = {0, target_.cols - 1, 0, target_.rows - 1};
  int outermost[4] = {target_.cols, -1, target_.rows, -1};
  for (int id : c.ids) {
    const Vec2 g = gridOf(target_, id);
    const int x = static_cast<int>(g.x()), y = static_cast<int>(g.y());
    outermost[0] = std::min(outermost[0], x), outermost[1] = std::max(outermost[1], x);
    outermost[2] = std::min(outermost[2], y), outermost[3] = std::max(outermost[3], y);
  }
  // Sampled 1.5 squares beyond the outermost corners, on either side of each. Beyond an edge corner
  // the outer square has ended there: the squares a board shifted by two squares would have there
  // must not show (whatever does: the margin, the wall, something in front of the board, matches
  // their alternating colours about half the time). Beyond corners short of the edge the board
  // goes on there (a corner row or the outer squares): where in view, its squares must show, or the
  // corners are numbered from the wrong end (a board slipped by two squares towards this side, its
  // real edge beside them, its outer corners dropped on the margin).
  const auto looksBlack = [&](double v) { return std::abs(v - means->first) < std::abs(v - means->second); };
  int samples[4] = {0, 0, 0, 0}, continuing[4] = {0, 0, 0, 0};
  for (int id : c.ids) {
    const Vec2 g = gridOf(target_, id);
    for (int side = 0; side < 4; ++side) {
      if ((side < 2 ? g.x() : g.y()) != outermost[side]) continue;
      const Vec2 along(outwards[side].y(), outwards[side].x());
      for (const double half : {-0.5, 0.5}) {
        const Vec2 centre = g + 1.5 * outwards[side] + half * along;
        const double v = sampleGrid(grey, camera, H, centre);
        if (v < 0) continue;
        // Square (a, b) is black when a + b is even (SPEC section 2; parity_ turns it).
        const int a = static_cast<int>(std::floor(centre.x())), b = static_cast<int>(std::floor(centre.y()));
        const bool black = ((a + b) % 2 == 0) == (parity_ > 0);
        ++samples[side];
        continuing[side] += looksBlack(v) == black;
      }
    }
  }
  for (int side = 0; side < 4; ++side) {
    if (samples[side] < kMinEdgeSamples) continue;
    const bool goes_on = continuing[side] > kMaxContinuingFraction * samples[side];
    if (goes_on != (outermost[side] != edge[side])) return false;
  }
  return true;
}

BoardCorners BoardCornerTracker::withReenteringCorners(const BoardCorners& c, const CameraModel& camera) const {
  if (c.complete || options_.min_partial_corners == 0) return c;
  // The homography from the grid to the undistorted normalised corners puts the missing ones.
  std::vector<Vec2> plane, xy;
  for (size_t k = 0; k < c.ids.size(); ++k) {
    plane.push_back(gridOf(target_, c.ids[k]));
    xy.push_back(camera.undistortPixel(Vec2(c.uv[k].x, c.uv[k].y)));
  }
  const Mat3 H = homographyDlt(plane, xy);
  const double margin = refineMarginPx(c);
  std::vector<char> have(target_.numCorners(), 0);
  for (int id : c.ids) have[id] = 1;
  BoardCorners out;
  size_t k = 0;
  for (int id = 0; id < target_.numCorners(); ++id) {
    if (have[id]) {
      out.ids.push_back(id);
      out.uv.push_back(c.uv[k++]);
      continue;
    }
    const Vec3 p = H * gridOf(target_, id).homogeneous();
    if (!(p.z() > 0)) continue;  // the plane's horizon: never in the image
    const Vec2 uv = camera.project(p / p.z());
    if (!camera.inImage(uv, margin)) continue;
    out.ids.push_back(id);
    out.uv.emplace_back(static_cast<float>(uv.x()), static_cast<float>(uv.y()));
  }
  out.complete = static_cast<int>(out.ids.size()) == target_.numCorners();
  return out;
}

std::optional<BoardCorners> BoardCornerTracker::predictedCorners(const cv::Mat& grey, const CameraModel& camera,
                                                                 const std::vector<cv::Point2f>& expected) const {
  BoardCorners all;
  for (int id = 0; id < static_cast<int>(expected.size()); ++id) {
    const Vec2 uv(expected[id].x, expected[id].y);
    if (!uv.allFinite() || !camera.inImage(uv, -100)) continue;
    all.ids.push_back(id);
    all.uv.push_back(expected[id]);
  }
  const double spacing = subsetSpacing(target_, all);
  if (!(spacing < kUnknownSpacing)) return std::nullopt;
  // Aligned within a radius that cannot reach the next corner.
  const int radius = std::max(3, static_cast<int>(std::min(options_.max_prediction_error_px, 0.45 * spacing)));
  const double margin = refineHalfWindow(spacing, options_.detector) + 2.0 + radius;
  BoardCorners in;
  for (size_t k = 0; k < all.ids.size(); ++k) {
    if (!camera.inImage(Vec2(all.uv[k].x, all.uv[k].y), margin)) continue;
    in.ids.push_back(all.ids[k]);
    in.uv.push_back(all.uv[k]);
  }
  if (static_cast<int>(in.ids.size()) < minCorners()) return std::nullopt;
  // Each predicted corner refined with a window as wide as the radius, almost a square (it
  // reaches the corner from up to the radius away, and no other corner); their median shift
  // moves the whole prediction (a pose error shifts the board as a whole).
  std::vector<cv::Point2f> wide = in.uv;
  // Only their median shift is used: cv::cornerSubPix's bias (core/subpixel_corner.h) is immaterial.
  cv::cornerSubPix(grey, wide, cv::Size(radius, radius), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 20, 0.01));
  std::vector<double> dx, dy;
  for (size_t k = 0; k < wide.size(); ++k) {
    dx.push_back(wide[k].x - in.uv[k].x);
    dy.push_back(wide[k].y - in.uv[k].y);
  }
  const cv::Point2f shift(static_cast<float>(median(dx)), static_cast<float>(median(dy)));
  // Most corners must agree on the shift: a board, not texture.
  int agree = 0;
  for (size_t k = 0; k < dx.size(); ++k) agree += std::hypot(dx[k] - shift.x, dy[k] - shift.y) <= 2.0;
  if (2 * agree < static_cast<int>(dx.size())) return std::nullopt;
  for (cv::Point2f& p : in.uv) p += shift;
  return in;
}

std::optional<BoardCorners> BoardCornerTracker::fullSearch(const cv::Mat& grey,
                                                           const std::vector<cv::Point2f>& expected,
                                                           const cv::Rect& region) {
  std::vector<cv::Point2f> uv;
  if (!detector_.detect(grey, region, &uv)) return std::nullopt;
  if (target_.symmetric()) {
    const bool all_expected = !expected.empty() && std::all_of(expected.begin(), expected.end(), [](const cv::Point2f& p) {
      return std::isfinite(p.x) && std::isfinite(p.y);
    });
    chooseSymmetricOrder(target_, uv, all_expected ? expected : last_seen_);
  }
  last_seen_ = uv;  // the detector has learnt from this view already
  BoardCorners c;
  c.uv = uv;
  c.ids.resize(uv.size());
  for (size_t k = 0; k < uv.size(); ++k) c.ids[k] = static_cast<int>(k);
  c.complete = true;
  // A symmetric board's numbering may put a white square outside corner 0: kept from here on.
  if (target_.symmetric()) {
    parity_ = 1.0;
    parity_ = squareContrast(grey, c) < 0 ? -1.0 : 1.0;
  }
  return c;
}

std::optional<std::vector<cv::Point2f>> BoardCornerTracker::searchWholeBoard(const cv::Mat& grey) {
  last_searched_whole_ = false;
  last_found_ = BoardFound::None;
  corners_ = {};
  if (!fullSearchDue(true, false)) return std::nullopt;
  auto found = fullSearch(grey, {}, cv::Rect(0, 0, grey.cols, grey.rows));
  if (!found) return std::nullopt;
  corners_ = std::move(*found);
  frames_since_search_ = kNeverSearched;
  last_found_ = BoardFound::Searched;
  return corners_.uv;
}

std::optional<BoardCorners> BoardCornerTracker::findCorners(const cv::Mat& grey,
                                                            const std::vector<cv::Mat>& pyramid_prev,
                                                            const std::vector<cv::Mat>& pyramid, cv::Size lk_window,
                                                            int lk_levels, const CameraModel& camera,
                                                            const SE3* T_world_camera_predicted, bool allow_search,
                                                            const std::vector<cv::Point2f>* uv_predicted) {
  last_searched_whole_ = false;
  last_found_ = BoardFound::None;
  const auto accept = [&](BoardCorners c, BoardFound how) {
    corners_ = std::move(c);
    if (corners_.complete) rememberWholeBoard(grey, corners_.uv);
    last_found_ = how;
    frames_since_search_ = kNeverSearched;
    return corners_;
  };
  const std::vector<cv::Point2f> expected = T_world_camera_predicted
                                                ? projectEveryBoardCorner(camera, target_, *T_world_camera_predicted)
                                            : uv_predicted ? *uv_predicted
                                                           : std::vector<cv::Point2f>{};
  if (options_.track && !corners_.ids.empty() && !pyramid_prev.empty()) {
    // Lucas-Kanade from where the predicted pose puts the corners (a fast turn moves them tens of
    // pixels), else from where they were.
    std::vector<cv::Point2f> uv = corners_.uv;
    int flags = 0;
    if (!expected.empty()) {
      std::vector<cv::Point2f> predicted;
      for (int id : corners_.ids) {
        if (!std::isfinite(expected[id].x) || !std::isfinite(expected[id].y)) break;
        predicted.push_back(expected[id]);
      }
      if (predicted.size() == corners_.ids.size()) uv = std::move(predicted), flags = cv::OPTFLOW_USE_INITIAL_FLOW;
    }
    std::vector<uchar> status;
    cv::calcOpticalFlowPyrLK(pyramid_prev, pyramid, corners_.uv, uv, status, cv::noArray(), lk_window, lk_levels,
                             kCoarseLk, flags);
    const double margin = refineMarginPx(corners_);
    BoardCorners tracked;
    for (size_t k = 0; k < uv.size(); ++k) {
      if (!status[k] || !camera.inImage(Vec2(uv[k].x, uv[k].y), margin)) continue;
      tracked.ids.push_back(corners_.ids[k]);
      tracked.uv.push_back(uv[k]);
    }
    tracked.complete = static_cast<int>(tracked.ids.size()) == target_.numCorners();
    if (static_cast<int>(tracked.ids.size()) >= minCorners()) {
      BoardCorners c = withReenteringCorners(tracked, camera);
      if (confirmCorners(grey, &c, camera)) return accept(std::move(c), BoardFound::Tracked);
    }
  }
  corners_ = {};
  if (!expected.empty() && options_.predicted_search) {
    if (auto c = predictedCorners(grey, camera, expected))
      if (confirmCorners(grey, &*c, camera)) return accept(std::move(*c), BoardFound::Predicted);
  }
  // Where the board is predicted, in every frame: a region a few times the board costs 1 to 5 ms
  // (35 with part of the board in it), the whole of a cluttered frame 100 to 600 ms. A region of
  // most of the image is left to the whole image's schedule.
  const cv::Rect region = allow_search ? predictedRegion(grey, expected) : cv::Rect();
  const bool large = 2.0 * region.area() > static_cast<double>(grey.total());
  if (!region.empty() && !large)
    if (auto found = fullSearch(grey, expected, region)) return accept(std::move(*found), BoardFound::Searched);
  if (!fullSearchDue(allow_search, !expected.empty() && !large)) return std::nullopt;
  auto found = fullSearch(grey, expected, cv::Rect(0, 0, grey.cols, grey.rows));
  if (!found) return std::nullopt;
  return accept(std::move(*found), BoardFound::Searched);
}

}  // namespace slamcmp
