#include "core/subpixel_corner.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace slamcmp {

void SubpixelCornerOptions::check() const {
  if (std::find(kMethods.begin(), kMethods.end(), method) == kMethods.end())
    throw OptionError("method", "must be gradient or opencv, got '" + method + "'");
  if (!(smoothing_sigma_px >= 0 && smoothing_sigma_px <= 5))
    throw OptionError("smoothing_sigma_px", "must be in [0, 5] pixels");
  if (max_iterations < 1) throw OptionError("max_iterations", "must be >= 1");
  if (!(epsilon_px > 0)) throw OptionError("epsilon_px", "must be positive");
}

namespace {

constexpr double kExtraRadiusOverHalfWindow = 0.7, kMaxExtraRadius = 3.0;  // pixels
constexpr double kMinDeterminantOverTrace2 = 0.01;
// cv::sepFilter2D's set-up costs about as much as smoothing this many pixels (one core: 5 us
// against 3.5 ns a pixel, OpenCV 4.6's float kernel of 13 taps).
constexpr double kSetUpPixels = 1500;

// The lens about a window's centre pixel: undistorted pixels m(d) - m(0) of the pixel d from it,
// to second order (central differences over +-kStep px), which holds the edges' bend. Through
// roll_distortion's lens, 200 px from the centre, the model is 0.002 px off 10 px from the window's
// centre, where the weights are small.
class LocalUndistortion {
 public:
  LocalUndistortion() = default;  // the identity
  LocalUndistortion(const CameraModel& camera, int cx, int cy) : identity_(false) {
    // The stencil's points undistorted from the centre's, linearly extrapolated: a few steps
    // fewer than from scratch.
    const Vec2 xy0 = camera.undistortPixel(Vec2(cx, cy));
    Mat2 J0;
    const Vec2 xyd0 = camera.distort(xy0, &J0);
    const Mat2 J0_inverse = J0.inverse();
    const auto m = [&](double du, double dv) {
      const Vec2 xy_distorted = camera.normalisedFromPixel(Vec2(cx + du, cy + dv));
      const Vec2 start = xy0 + J0_inverse * (xy_distorted - xyd0);
      return camera.pixelFromNormalised(camera.undistort(xy_distorted, &start));
    };
    const Vec2 m0 = camera.pixelFromNormalised(xy0), mx1 = m(kStep, 0), mx0 = m(-kStep, 0), my1 = m(0, kStep),
               my0 = m(0, -kStep);
    const double h2 = kStep * kStep;
    A_.col(0) = (mx1 - mx0) / (2 * kStep);
    A_.col(1) = (my1 - my0) / (2 * kStep);
    const Vec2 xx = (mx1 - 2 * m0 + mx0) / h2, yy = (my1 - 2 * m0 + my0) / h2,
               xy = (m(kStep, kStep) - m(kStep, -kStep) - m(-kStep, kStep) + m(-kStep, -kStep)) / (4 * h2);
    for (int k = 0; k < 2; ++k) H_[k] << xx(k), xy(k), xy(k), yy(k);
    // Beyond a fold of the lens (a camera file refuses one, core/distortion_fold.h) the model
    // means nothing: the corner is fitted in the image.
    if (!(A_.allFinite() && H_[0].allFinite() && H_[1].allFinite() && A_.determinant() > 0)) *this = {};
  }
  bool identity() const { return identity_; }
  // m(u, v) and its Jacobian dm/d(u, v), written out: the terms of every pixel of a window take
  // it (bench_stages BM_CornerRefinement, tv1: 28 us a board less than through Eigen's types).
  void map(double u, double v, double m[2], double J[2][2]) const {
    for (int k = 0; k < 2; ++k) {
      const double hu = H_[k](0, 0) * u + H_[k](0, 1) * v, hv = H_[k](1, 0) * u + H_[k](1, 1) * v;
      J[k][0] = A_(k, 0) + hu, J[k][1] = A_(k, 1) + hv;
      m[k] = A_(k, 0) * u + A_(k, 1) * v + 0.5 * (u * hu + v * hv);
    }
  }
  Vec2 map(const Vec2& d, Mat2* J_out = nullptr) const {
    if (identity_) {
      if (J_out) J_out->setIdentity();
      return d;
    }
    double m[2], J[2][2];
    map(d.x(), d.y(), m, J);
    if (J_out) *J_out << J[0][0], J[0][1], J[1][0], J[1][1];
    return Vec2(m[0], m[1]);
  }
  // The d that maps to m, from d near it (Newton).
  Vec2 unmap(const Vec2& m, Vec2 d) const {
    if (identity_) return m;
    for (int k = 0; k < 3; ++k) {
      Mat2 J;
      const Vec2 r = map(d, &J) - m;
      d -= J.inverse() * r;
    }
    return d;
  }

 private:
  static constexpr double kStep = 4;  // pixels
  bool identity_ = true;
  Mat2 A_ = Mat2::Identity();
  Mat2 H_[2] = {Mat2::Zero(), Mat2::Zero()};
};

// The image smoothed by a Gaussian (OpenCV's float kernel, reaching 4 sigma) and the terms of the
// corner's equations on the square of pixels within `reach` of (cx, cy), from the smoothed values
// one pixel beyond it (central differences). The smoothing reads the image around the square in
// place and replicates it beyond its border. It is done once for all the corners of a board when
// that costs less than square by square, counting cv::sepFilter2D's set-up as kSetUpPixels
// (bench_stages BM_CornerRefinement, tv1's 54 corners at half window 5: 701 us apart, 452-503
// together).
class GradientWindow {
 public:
  GradientWindow(const cv::Mat& grey, double sigma) : grey_(grey) {
    const int ksize = sigma > 0 ? cvRound(sigma * 4 * 2 + 1) | 1 : 1;  // cv::GaussianBlur's, float image
    kernel_ = sigma > 0 ? cv::getGaussianKernel(ksize, sigma, CV_32F) : cv::Mat(1, 1, CV_32F, cv::Scalar(1));
  }

  // The region holding every corner's square (and two pixels more, for the moves of its centre),
  // smoothed at once when that costs less than the squares one by one.
  void smoothAround(const std::vector<cv::Point2f>& uv, int reach) {
    constexpr int kMoves = 2;  // a corner's start is a track or a prediction, within a pixel or two
    const int extent = reach + 1 + kMoves;
    const cv::Rect image(0, 0, grey_.cols, grey_.rows);
    cv::Rect region;
    double squares = 0;
    for (const cv::Point2f& p : uv) {
      if (!(p.x >= 0 && p.y >= 0 && p.x < grey_.cols && p.y < grey_.rows)) continue;  // NaN too
      const cv::Rect square(cvRound(p.x) - extent, cvRound(p.y) - extent, 2 * extent + 1, 2 * extent + 1);
      region = region.area() == 0 ? square : (region | square);
      squares += square.area() + kSetUpPixels;
    }
    region &= image;
    region_ = cv::Mat();
    if (region.area() == 0 || region.area() > squares) return;
    cv::sepFilter2D(grey_(region), region_, CV_32F, kernel_, kernel_, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
    region_rect_ = region;
  }

  // False where the square and the pixel around it are not all in the image. With a lens the
  // terms are those of the undistorted image (gradients and offsets mapped by it).
  bool centre(int cx, int cy, int reach, const LocalUndistortion& lens) {
    side_ = 2 * reach + 1;
    const int core = reach + 1, n = 2 * core + 1;
    const cv::Rect square(cx - core, cy - core, n, n);
    if ((square & cv::Rect(0, 0, grey_.cols, grey_.rows)) != square) return false;
    if (!region_.empty() && (square & region_rect_) == square) {
      smooth_ = region_(square - region_rect_.tl());
    } else {
      cv::sepFilter2D(grey_(square), own_, CV_32F, kernel_, kernel_, cv::Point(-1, -1), 0, cv::BORDER_REPLICATE);
      smooth_ = own_;
    }
    terms_.resize(static_cast<size_t>(side_) * side_);
    // Only the pixels refineCorner reads: within its radius R <= reach - 0.5 of a corner at most
    // sqrt(0.5) px from the centre, so at most reach + 0.21 px from it (the square's corners, a
    // fifth of it, would take the lens's map for nothing).
    const double read2 = (reach + 0.25) * (reach + 0.25);
    for (int v = 0; v < side_; ++v)
      for (int u = 0; u < side_; ++u) {
        double du = u - reach, dv = v - reach;
        if (du * du + dv * dv > read2) continue;
        const float* above = smooth_.ptr<float>(v);
        const float* row = smooth_.ptr<float>(v + 1);
        const float* below = smooth_.ptr<float>(v + 2);
        const double gx = 0.5 * (row[u + 2] - row[u]), gy = 0.5 * (below[u + 1] - above[u + 1]);
        double gxx = gx * gx, gxy = gx * gy, gyy = gy * gy;
        if (!lens.identity()) {
          // I(p) = I'(m(p)): the undistorted image's gradient points along J^-T g, as h = adj(J)^T g
          // does; only its direction is kept. Its magnitude stays the image's: the blur is
          // symmetric across each edge there, and a magnitude scaled by the lens (more on one side
          // of an edge than on the other) pulls the corner across it: 0.008 px inwards on
          // EdgesBentByTheLensAreTakenStraight's corners, 0.0005 without.
          double m[2], J[2][2];
          lens.map(du, dv, m, J);
          const double hx = J[1][1] * gx - J[1][0] * gy, hy = J[0][0] * gy - J[0][1] * gx, h2 = hx * hx + hy * hy;
          const double scale2 = h2 > 0 ? (gxx + gyy) / h2 : 0;
          gxx = hx * hx * scale2, gxy = hx * hy * scale2, gyy = hy * hy * scale2;
          du = m[0], dv = m[1];
        }
        Terms& t = terms_[static_cast<size_t>(v) * side_ + u];
        t.gxx = gxx, t.gxy = gxy, t.gyy = gyy;
        t.px = gxx * du + gxy * dv, t.py = gxy * du + gyy * dv;
      }
    return true;
  }
  // Per pixel, g g^T and g g^T p, p from the centre.
  struct Terms {
    double gxx, gxy, gyy, px, py;
  };
  // Pixel (du, dv) from the centre, within reach.
  const Terms& at(int du, int dv) const {
    const int reach = side_ / 2;
    return terms_[static_cast<size_t>(dv + reach) * side_ + du + reach];
  }

 private:
  const cv::Mat& grey_;
  cv::Mat kernel_;
  cv::Mat region_;        // the image smoothed over region_rect_, or empty
  cv::Rect region_rect_;
  cv::Mat own_;           // a square smoothed on its own
  cv::Mat smooth_;        // the centred square's smoothed values (in region_ or own_)
  std::vector<Terms> terms_;
  int side_ = 0;
};

double maxRadius(int half) { return half + 0.5 + std::min(kExtraRadiusOverHalfWindow * half, kMaxExtraRadius); }
int reachOf(double radius) { return static_cast<int>(std::ceil(radius + 0.5)); }  // q within half a pixel of the centre

// One corner; false (and `corner` unchanged) when its window has no junction or leaves the image.
bool refineCorner(const cv::Mat& grey, int half, const SubpixelCornerOptions& options, const CameraModel* camera,
                  GradientWindow& window, cv::Point2f* corner) {
  // The weights reach about as far as cv::cornerSubPix's square window does along its diagonal
  // (at most 3 px beyond the circle inside it): with that inner circle (half + 0.5) the real
  // views' small windows (half 2-3 on Bouguet's images) hold too few pixels against the noise, and
  // corners ran off by pixels. Near the image's border the circle shrinks to what the image holds,
  // down to half + 0.5.
  const double border = std::min({corner->x, corner->y, grey.cols - 1 - corner->x, grey.rows - 1 - corner->y});
  if (!(border >= 0)) return false;  // off the image, or not a number
  const double radius = std::min(maxRadius(half), std::max(half + 0.5, border - 2.5));
  const double radius2 = radius * radius, inverse_radius2 = 1 / radius2;
  const int reach = reachOf(radius);
  double qx = corner->x, qy = corner->y;
  int cx = 0, cy = 0;  // the pixel the window is centred on
  bool have_window = false;
  LocalUndistortion lens;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const int ix = static_cast<int>(std::lround(qx)), iy = static_cast<int>(std::lround(qy));
    if (!have_window || ix != cx || iy != cy) {
      if (camera) lens = LocalUndistortion(*camera, ix, iy);
      if (!window.centre(ix, iy, reach, lens)) return false;
      cx = ix, cy = iy, have_window = true;
    }
    // sum_p w g g^T (p - q_new) = 0, i.e. A (q_new - q) = sum_p w g g^T (p - q) = sum_p w g g^T p - A q,
    // with the weights (1 - r^2 / R^2)^2 of r = |p - q|; p and q from the window's centre, in the
    // undistorted image with a lens (the weights in the image).
    const double ox = qx - cx, oy = qy - cy;
    Mat2 J_o;
    const Vec2 o_undistorted = lens.map(Vec2(ox, oy), &J_o);
    double a = 0, b = 0, c = 0, sx = 0, sy = 0;
    for (int dv = -reach; dv <= reach; ++dv) {
      const double dy = dv - oy;
      const double t = 1 - dy * dy * inverse_radius2;  // 1 - r^2 / R^2 with dx = 0
      if (t <= 0) continue;
      const double half_width = std::sqrt(t * radius2);
      const int first = std::max(-reach, static_cast<int>(std::ceil(ox - half_width)));
      const int last = std::min(reach, static_cast<int>(std::floor(ox + half_width)));
      for (int du = first; du <= last; ++du) {
        const double dx = du - ox;
        const double s = t - dx * dx * inverse_radius2;
        const double w = s > 0 ? s * s : 0;
        const GradientWindow::Terms& g = window.at(du, dv);
        a += w * g.gxx, b += w * g.gxy, c += w * g.gyy;
        sx += w * g.px, sy += w * g.py;
      }
    }
    const double rx = sx - (a * o_undistorted.x() + b * o_undistorted.y()),
                 ry = sy - (b * o_undistorted.x() + c * o_undistorted.y());
    const double det = a * c - b * b;
    // Both directions of gradient needed: a lone edge (or a flat window) places no corner. The
    // ratio is 0.25 at a right-angled junction, above 0.03 at a 20-degree one.
    if (!(det > kMinDeterminantOverTrace2 * (a + c) * (a + c))) return false;
    double step_x = (c * rx - b * ry) / det, step_y = (a * ry - b * rx) / det;
    if (!lens.identity()) {  // the step in the undistorted image, mapped back
      const Vec2 o_new_undistorted = o_undistorted + Vec2(step_x, step_y);
      const Vec2 d_new = lens.unmap(o_new_undistorted, Vec2(ox, oy) + J_o.inverse() * Vec2(step_x, step_y));
      step_x = d_new.x() - ox, step_y = d_new.y() - oy;
    }
    qx += step_x, qy += step_y;
    // Run out of its window: the junction was not where the corner started (on Bouguet's images a
    // weak window ran 80 px).
    if (!(std::hypot(qx - corner->x, qy - corner->y) <= radius)) return false;  // NaN fails too
    if (step_x * step_x + step_y * step_y < options.epsilon_px * options.epsilon_px) break;
  }
  *corner = cv::Point2f(static_cast<float>(qx), static_cast<float>(qy));
  return true;
}

}  // namespace

void refineCornersSubpixel(const cv::Mat& grey, int half_window, std::vector<cv::Point2f>& uv,
                           const SubpixelCornerOptions& options, const CameraModel* camera) {
  CV_Assert(grey.type() == CV_8UC1 && half_window >= 1);
  CV_Assert(!camera || (grey.cols == camera->width && grey.rows == camera->height));  // pixels are the camera's
  const auto opencv = [&](std::vector<cv::Point2f>& corners) {
    if (corners.empty()) return;
    cv::cornerSubPix(grey, corners, cv::Size(half_window, half_window), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, options.max_iterations,
                                      options.epsilon_px));
  };
  if (options.method == "opencv") return opencv(uv);
  // The smoothing reads the image around its windows in place: a region of a larger image (the
  // board searched for where it may be) is copied, so that its border is the border.
  const cv::Mat image = grey.isSubmatrix() ? grey.clone() : grey;
  // A blur wide against the window leaves no junction to place (half window 3, before the radius
  // grew: 0.36 px RMS at 1.5 px against 0.021 at 0.75): at most half the window beyond 1.5 px.
  GradientWindow window(image, std::clamp(0.5 * (half_window - 1.5), 0.0, options.smoothing_sigma_px));
  window.smoothAround(uv, reachOf(maxRadius(half_window)));
  const CameraModel* undistorting = options.undistorted && camera && camera->hasDistortion() ? camera : nullptr;
  std::vector<cv::Point2f> unplaced;
  std::vector<size_t> where;
  for (size_t k = 0; k < uv.size(); ++k)
    if (!refineCorner(image, half_window, options, undistorting, window, &uv[k])) {
      unplaced.push_back(uv[k]);
      where.push_back(k);
    }
  opencv(unplaced);
  for (size_t k = 0; k < where.size(); ++k) uv[where[k]] = unplaced[k];
}

}  // namespace slamcmp
