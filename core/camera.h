#pragma once
// Pinhole camera with OpenCV's distortion model (4, 5 or 8 coefficients), analytic Jacobians.
// Naming: xy_* are normalised image coordinates (z = 1), uv_* are pixels; *_distorted is what the
// sensor sees, *_undistorted the ideal pinhole image.
#include <array>
#include <string>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "core/geometry.h"

namespace slamcmp {

struct CameraModel {
  int width = 0;   // pixels
  int height = 0;  // pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels
  double skew = 0;                        // K(0,1); zero for nearly every camera
  // OpenCV order k1 k2 p1 p2 k3 k4 k5 k6; num_distortion of them are meaningful (4, 5 or 8).
  std::array<double, 8> distortion{};
  int num_distortion = 5;

  bool hasDistortion() const;
  // Throws InputError naming `where` if a value is impossible (sizes, focal lengths, count).
  void check(const std::string& where) const;

  // Normalised pinhole coordinates -> distorted normalised coordinates; J = d xy_distorted / d xy.
  Vec2 distort(const Vec2& xy_undistorted, Mat2* J = nullptr) const;
  // Inverse of distort by Gauss-Newton (a few iterations; exact to ~1e-12 inside the image), from
  // `start` if given (a point near the answer: fewer iterations), else from xy_distorted.
  Vec2 undistort(const Vec2& xy_distorted, const Vec2* start = nullptr) const;

  Vec2 pixelFromNormalised(const Vec2& xy) const;
  Vec2 normalisedFromPixel(const Vec2& uv) const;

  // Full projection of a point in the camera frame to a distorted pixel. J = d uv / d p_camera.
  // The point must be in front of the camera (z > 0).
  Vec2 project(const Vec3& p_camera, Eigen::Matrix<double, 2, 3>* J = nullptr) const;
  // Distorted pixel -> undistorted normalised coordinates (the ray (x, y, 1)).
  Vec2 undistortPixel(const Vec2& uv_distorted) const;
  // Distorted pixel -> undistorted pixel (same K, no distortion).
  Vec2 undistortToPixel(const Vec2& uv_distorted) const;

  bool inImage(const Vec2& uv, double margin = 0.0) const;
  // A rolling shutter reading the rows top to bottom in `readout` seconds: when row v (pixels) is
  // read, relative to the frame's time, the middle row's.
  double rowTime(double readout, double v) const { return readout * (v / (height - 1.0) - 0.5); }

  cv::Mat cameraMatrix() const;      // 3x3 CV_64F
  cv::Mat distortionVector() const;  // 1 x num_distortion CV_64F
  Mat3 K() const;
  static CameraModel fromOpenCV(const cv::Mat& camera_matrix, const cv::Mat& dist, cv::Size size);
};

// Focal lengths and principal point a real camera of this image size can have; anything else is a
// unit mix-up (millimetres, another resolution) or a typo, and would only show up as a lost run.
// Then a distortion that does not fold over the image (core/distortion_fold.h).
// Throws InputError naming `path` and `field` (the file's name for the focal lengths and principal
// point) or distortion_coefficients.
void checkPlausibleIntrinsics(const CameraModel& camera, const std::string& path, const std::string& field);

// camera.yaml (OpenCV FileStorage): image_width, image_height, camera_matrix, distortion_coefficients.
CameraModel readCameraYaml(const std::string& path);
void writeCameraYaml(const std::string& path, const CameraModel& camera, double rms_px = -1.0);

}  // namespace slamcmp
