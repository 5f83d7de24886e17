#pragma once
// Renders grey images of a Scene through a CameraModel, distortion included: every output pixel
// is split into n x n samples, each undistorted to a ray, cast into the scene and shaded; the
// samples are averaged (anti-aliasing). Then the optics' blur, and optionally motion blur,
// illumination change and sensor noise.
#include <cstdint>
#include <functional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "datasets/scene.h"

namespace slamcmp {

struct FrameEffects {
  double lens_blur = 0.7;     // Gaussian point spread of the optics, sigma in pixels (0: none)
  double noise_sigma = 0.0;   // grey levels, Gaussian, independent per pixel
  double blur_px = 0.0;       // length of the motion streak at the image centre, pixels
  double illumination = 0.0;  // relative amplitude of a slow change of the overall brightness
  double rolling_shutter = 0.0;  // seconds from reading the top row to the bottom row (0: global)
};

class SceneRenderer {
 public:
  // Precomputes the rays of all samples (the same in every frame). Uses every core. The scene must
  // outlive the renderer.
  SceneRenderer(const CameraModel& camera, const Scene& scene, int samples_per_axis);

  // Noise-free grey levels (CV_32F) seen from one pose.
  cv::Mat radiance(const SE3& T_world_camera) const;
  // The same through a rolling shutter: row v seen from T_world_camera_at(t + camera.rowTime(readout,
  // v)), the middle row at t. T_world_camera_at is called from several threads at once.
  cv::Mat radiance(const std::function<SE3(double)>& T_world_camera_at, double t, double readout) const;

  // The 8-bit frame at time t (seconds) of a camera moving along `T_world_camera_at`: the
  // exposure is centred on t, so the frame's ground truth is T_world_camera_at(t). Motion blur
  // averages renders over an exposure (at most one frame_interval) chosen so that the image centre
  // moves blur_px pixels; a rolling shutter reads each row of each of those renders at its own time
  // (T_world_camera_at is then called from several threads at once).
  // `seed` and `frame_index` fix the noise.
  cv::Mat renderFrame(const std::function<SE3(double)>& T_world_camera_at, double t,
                      double frame_interval, const FrameEffects& effects, std::uint64_t seed,
                      int frame_index) const;

  const CameraModel& camera() const { return camera_; }

 private:
  CameraModel camera_;
  const Scene& scene_;
  int samples_;                 // per axis
  std::vector<float> xy_;       // undistorted normalised ray (x, y) of each sample, pixel-major
};

}  // namespace slamcmp
