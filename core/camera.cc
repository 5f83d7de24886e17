#include "core/camera.h"

#include <cmath>
#include <sstream>
#include <utility>

#include "core/distortion_fold.h"
#include "core/error.h"
#include "core/yaml.h"

namespace slamcmp {

namespace {

std::string formatNumber(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// An integer `dt` (u, c, w, s, i) makes OpenCV round the values it reads (fx 150.7 -> 151) or wrap
// them (an 8-bit 500 -> 244): refused rather than silently read.
void requireFloatingPoint(const YamlFile& file, const std::string& key) {
  const cv::FileNode n = file.node(key);
  if (!n.isMap()) return;  // a plain list, or missing: getMatrix() reports what is wrong
  const cv::FileNode dt = n["dt"];
  if (dt.empty()) return;
  const std::string type = dt.isString() ? static_cast<std::string>(dt) : std::string("?");
  if (type != "f" && type != "d")
    throw InputError(file.path() + ": " + key + ".dt",
                     "must be f or d (floating point), got '" + type + "': integer data would be rounded");
}

}  // namespace

void checkPlausibleIntrinsics(const CameraModel& c, const std::string& path, const std::string& field) {
  const std::string where = path + ": " + field;
  const std::string size = std::to_string(c.width) + "x" + std::to_string(c.height);
  const double lo = 0.05 * c.width, hi = 100.0 * c.width;
  for (const auto& [name, f] : {std::pair<const char*, double>{"fx", c.fx}, {"fy", c.fy}})
    if (!(f >= lo && f <= hi))  // NaN too
      throw InputError(where, std::string(name) + " " + formatNumber(f) + " px is not plausible for " + size +
                                  " images (expected " + formatNumber(lo) + " to " + formatNumber(hi) + " px)");
  if (!(c.cx >= -0.5 * c.width && c.cx <= 1.5 * c.width))
    throw InputError(where, "cx " + formatNumber(c.cx) + " px is far outside the " + size + " image");
  if (!(c.cy >= -0.5 * c.height && c.cy <= 1.5 * c.height))
    throw InputError(where, "cy " + formatNumber(c.cy) + " px is far outside the " + size + " image");
  // skew = -fx cot(angle between the pixel axes): a real sensor's axes are square to far better
  // than the 0.6 degrees of 0.01 fx, and calibrations that estimate skew find far less (Zhang's
  // published one: 0.2 px of fx 832, 0.00025 fx); more is a misplaced element or a typo (1e6 ran
  // with 435 m of error).
  const double max_skew = 0.01 * c.fx;
  if (!(std::abs(c.skew) <= max_skew))
    throw InputError(where, "skew (K[0][1]) " + formatNumber(c.skew) + " px is not plausible (expected at most " +
                                formatNumber(max_skew) + " px, 0.01 fx; nearly every camera has 0)");
  if (const std::string fold = distortionFold(c); !fold.empty())
    throw InputError(path + ": distortion_coefficients", fold);
}

bool CameraModel::hasDistortion() const {
  for (int i = 0; i < num_distortion; ++i)
    if (distortion[i] != 0.0) return true;
  return false;
}

void CameraModel::check(const std::string& where) const {
  if (width <= 0 || height <= 0)
    throw InputError(where, "image size must be positive, got " + std::to_string(width) + "x" +
                                std::to_string(height));
  if (!(fx > 0) || !(fy > 0) || !std::isfinite(fx) || !std::isfinite(fy))
    throw InputError(where, "camera_matrix focal lengths must be positive and finite");
  if (!std::isfinite(cx) || !std::isfinite(cy) || !std::isfinite(skew))
    throw InputError(where, "camera_matrix has a non-finite value");
  if (num_distortion != 4 && num_distortion != 5 && num_distortion != 8)
    throw InputError(where, "distortion_coefficients must have 4, 5 or 8 values, got " +
                                std::to_string(num_distortion));
  for (int i = 0; i < 8; ++i)
    if (!std::isfinite(distortion[i]))
      throw InputError(where, "distortion_coefficients has a non-finite value");
}

Vec2 CameraModel::distort(const Vec2& xy, Mat2* J) const {
  const auto& d = distortion;
  const double k1 = d[0], k2 = d[1], p1 = d[2], p2 = d[3], k3 = d[4], k4 = d[5], k5 = d[6], k6 = d[7];
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y, r4 = r2 * r2, r6 = r4 * r2;
  const double num = 1 + k1 * r2 + k2 * r4 + k3 * r6;
  const double den = 1 + k4 * r2 + k5 * r4 + k6 * r6;
  const double radial = num / den;
  const Vec2 out(x * radial + 2 * p1 * x * y + p2 * (r2 + 2 * x * x),
                 y * radial + p1 * (r2 + 2 * y * y) + 2 * p2 * x * y);
  if (J) {
    const double dnum = k1 + 2 * k2 * r2 + 3 * k3 * r4;
    const double dden = k4 + 2 * k5 * r2 + 3 * k6 * r4;
    const double drad = (dnum * den - num * dden) / (den * den);  // d radial / d r2
    (*J)(0, 0) = radial + 2 * x * x * drad + 2 * p1 * y + 6 * p2 * x;
    (*J)(0, 1) = 2 * x * y * drad + 2 * p1 * x + 2 * p2 * y;
    (*J)(1, 0) = 2 * x * y * drad + 2 * p1 * x + 2 * p2 * y;
    (*J)(1, 1) = radial + 2 * y * y * drad + 6 * p1 * y + 2 * p2 * x;
  }
  return out;
}

Vec2 CameraModel::undistort(const Vec2& xy_distorted, const Vec2* start) const {
  if (!hasDistortion()) return xy_distorted;
  Vec2 xy = start ? *start : xy_distorted;
  for (int it = 0; it < 20; ++it) {
    Mat2 J;
    const Vec2 r = distort(xy, &J) - xy_distorted;
    const Vec2 step = J.partialPivLu().solve(r);
    if (!step.allFinite()) break;
    xy -= step;
    if (step.squaredNorm() < 1e-24) break;
  }
  return xy;
}

Vec2 CameraModel::pixelFromNormalised(const Vec2& xy) const {
  return Vec2(fx * xy.x() + skew * xy.y() + cx, fy * xy.y() + cy);
}

Vec2 CameraModel::normalisedFromPixel(const Vec2& uv) const {
  const double y = (uv.y() - cy) / fy;
  return Vec2((uv.x() - cx - skew * y) / fx, y);
}

Vec2 CameraModel::project(const Vec3& p, Eigen::Matrix<double, 2, 3>* J) const {
  const double iz = 1.0 / p.z();
  const Vec2 xy(p.x() * iz, p.y() * iz);
  Mat2 Jd;
  const Vec2 xyd = distort(xy, J ? &Jd : nullptr);
  if (J) {
    const Mat23 Jp = pinholeJacobian(p);  // d xy / d p
    Mat2 Jk;  // d uv / d xy_distorted
    Jk << fx, skew, 0, fy;
    *J = Jk * Jd * Jp;
  }
  return pixelFromNormalised(xyd);
}

Vec2 CameraModel::undistortPixel(const Vec2& uv_distorted) const {
  return undistort(normalisedFromPixel(uv_distorted));
}

Vec2 CameraModel::undistortToPixel(const Vec2& uv_distorted) const {
  return pixelFromNormalised(undistortPixel(uv_distorted));
}

bool CameraModel::inImage(const Vec2& uv, double margin) const {
  // Pixel centres run from 0 to width-1; the image covers [-0.5, width-0.5).
  return uv.x() >= -0.5 + margin && uv.y() >= -0.5 + margin && uv.x() < width - 0.5 - margin &&
         uv.y() < height - 0.5 - margin;
}

cv::Mat CameraModel::cameraMatrix() const {
  return (cv::Mat_<double>(3, 3) << fx, skew, cx, 0, fy, cy, 0, 0, 1);
}

cv::Mat CameraModel::distortionVector() const {
  cv::Mat d(1, num_distortion, CV_64F);
  for (int i = 0; i < num_distortion; ++i) d.at<double>(i) = distortion[i];
  return d;
}

Mat3 CameraModel::K() const {
  Mat3 k;
  k << fx, skew, cx, 0, fy, cy, 0, 0, 1;
  return k;
}

CameraModel CameraModel::fromOpenCV(const cv::Mat& camera_matrix, const cv::Mat& dist, cv::Size size) {
  CameraModel c;
  cv::Mat K;
  camera_matrix.convertTo(K, CV_64F);
  c.width = size.width;
  c.height = size.height;
  c.fx = K.at<double>(0, 0);
  c.skew = K.at<double>(0, 1);
  c.cx = K.at<double>(0, 2);
  c.fy = K.at<double>(1, 1);
  c.cy = K.at<double>(1, 2);
  cv::Mat d;
  dist.convertTo(d, CV_64F);
  const int n = static_cast<int>(d.total());
  c.num_distortion = n <= 4 ? 4 : (n == 5 ? 5 : 8);
  for (int i = 0; i < std::min(n, 8); ++i) c.distortion[i] = d.at<double>(i);
  return c;
}

CameraModel readCameraYaml(const std::string& path) {
  YamlFile file(path);
  CameraModel c;
  c.width = file.getInt("image_width");
  c.height = file.getInt("image_height");
  requireFloatingPoint(file, "camera_matrix");
  requireFloatingPoint(file, "distortion_coefficients");
  const cv::Mat K = file.getMatrix("camera_matrix");
  if (K.rows != 3 || K.cols != 3)
    throw InputError(path + ": camera_matrix", "must be 3x3, got " + std::to_string(K.rows) + "x" +
                                                   std::to_string(K.cols));
  if (K.at<double>(1, 0) != 0 || K.at<double>(2, 0) != 0 || K.at<double>(2, 1) != 0 ||
      K.at<double>(2, 2) != 1)
    throw InputError(path + ": camera_matrix", "bottom rows must be [0 fy cy; 0 0 1]");
  const cv::Mat d = file.getMatrix("distortion_coefficients");
  const int n = static_cast<int>(d.total());
  if (n != 4 && n != 5 && n != 8)
    throw InputError(path + ": distortion_coefficients",
                     "must have 4, 5 or 8 values, got " + std::to_string(n));
  c = CameraModel::fromOpenCV(K, d, cv::Size(c.width, c.height));
  c.num_distortion = n;
  c.check(path);
  checkPlausibleIntrinsics(c, path, "camera_matrix");
  return c;
}

void writeCameraYaml(const std::string& path, const CameraModel& camera, double rms_px) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::WRITE);
  } catch (const cv::Exception&) {
  }
  if (!fs.isOpened()) throw InputError(path, "cannot be written");
  fs << "image_width" << camera.width << "image_height" << camera.height;
  fs << "camera_matrix" << camera.cameraMatrix();
  fs << "distortion_coefficients" << camera.distortionVector();
  if (rms_px >= 0) fs << "reprojection_rms_px" << rms_px;
}

}  // namespace slamcmp
