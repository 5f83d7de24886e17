#include "datasets/scene_renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <optional>
#include <thread>

#include <opencv2/imgproc.hpp>

namespace slamcmp {

namespace {

// Calls body(row_begin, row_end) on blocks of [0, rows) from one thread per core.
void parallelForRows(int rows, const std::function<void(int, int)>& body) {
  const int threads = std::max(1, std::min(static_cast<int>(std::thread::hardware_concurrency()), rows));
  constexpr int kBlock = 8;  // rows per task: small enough to balance uneven rows
  std::atomic<int> next{0};
  auto worker = [&] {
    for (int begin; (begin = next.fetch_add(kBlock)) < rows;) body(begin, std::min(rows, begin + kBlock));
  };
  std::vector<std::thread> pool;
  for (int k = 1; k < threads; ++k) pool.emplace_back(worker);
  worker();
  for (auto& th : pool) th.join();
}

}  // namespace

SceneRenderer::SceneRenderer(const CameraModel& camera, const Scene& scene, int samples_per_axis)
    : camera_(camera), scene_(scene), samples_(samples_per_axis) {
  const int n = samples_;
  const size_t per_pixel = static_cast<size_t>(n) * n;
  xy_.resize(2 * per_pixel * camera.width * camera.height);
  parallelForRows(camera.height, [&](int begin, int end) {
    for (int v = begin; v < end; ++v)
      for (int u = 0; u < camera_.width; ++u) {
        float* out = &xy_[2 * per_pixel * (static_cast<size_t>(v) * camera_.width + u)];
        // Pixel (u, v) covers [u - 0.5, u + 0.5] x [v - 0.5, v + 0.5]; samples at the centres of an
        // n x n grid over it.
        for (int b = 0; b < n; ++b)
          for (int a = 0; a < n; ++a) {
            const Vec2 uv(u - 0.5 + (a + 0.5) / n, v - 0.5 + (b + 0.5) / n);
            const Vec2 xy = camera_.undistortPixel(uv);
            *out++ = static_cast<float>(xy.x());
            *out++ = static_cast<float>(xy.y());
          }
      }
  });
}

cv::Mat SceneRenderer::radiance(const SE3& T_world_camera) const {
  return radiance([&T_world_camera](double) { return T_world_camera; }, 0.0, 0.0);
}

cv::Mat SceneRenderer::radiance(const std::function<SE3(double)>& T_world_camera_at, double t,
                                double readout) const {
  // One sample's angular width: 1 / (f n) radians.
  const double footprint = 1.0 / (std::max(camera_.fx, camera_.fy) * samples_);
  const SceneView still(scene_, T_world_camera_at(t), footprint);
  cv::Mat out(camera_.height, camera_.width, CV_32F);
  const int per_pixel = samples_ * samples_;
  parallelForRows(camera_.height, [&](int begin, int end) {
    for (int v = begin; v < end; ++v) {
      std::optional<SceneView> row_view;
      if (readout > 0)
        row_view.emplace(scene_, T_world_camera_at(t + camera_.rowTime(readout, v)), footprint);
      const SceneView& view = row_view ? *row_view : still;
      float* row = out.ptr<float>(v);
      const float* xy = &xy_[2 * static_cast<size_t>(per_pixel) * v * camera_.width];
      for (int u = 0; u < camera_.width; ++u) {
        double sum = 0;
        for (int k = 0; k < per_pixel; ++k, xy += 2) sum += view.radiance(xy[0], xy[1]);
        row[u] = static_cast<float>(sum / per_pixel);
      }
    }
  });
  return out;
}

cv::Mat SceneRenderer::renderFrame(const std::function<SE3(double)>& T_world_camera_at, double t,
                                   double frame_interval, const FrameEffects& effects, std::uint64_t seed,
                                   int frame_index) const {
  const SE3 T_world_camera = T_world_camera_at(t);
  cv::Mat image;
  if (effects.blur_px > 0) {
    // Image speed at the centre: where the scene point on the optical axis moves in one frame.
    const Vec3 p_world = SceneView(scene_, T_world_camera).intersect(0, 0).p_world;
    const double half = 0.5 * frame_interval;
    const Vec2 uv_before = camera_.project(T_world_camera_at(t - half).inverse() * p_world);
    const Vec2 uv_after = camera_.project(T_world_camera_at(t + half).inverse() * p_world);
    const double px_per_frame = (uv_after - uv_before).norm();
    const double exposure = px_per_frame > effects.blur_px ? effects.blur_px / px_per_frame : 1.0;
    const double streak = exposure * px_per_frame;
    // About one render per pixel of streak, so the average is smooth; each at the middle of its
    // share of the exposure (the midpoint rule), so that the mean over the renders is the mean
    // over the exposure: renders at both ends weighed the ends as much as the rest, and put an
    // accelerating image's mean 0.07 of its acceleration (pixels/frame^2) off with 4 renders,
    // where a sensor integrating the exposure gives 1/24 (hybrid/exposure_shift.h).
    const int renders = std::clamp(static_cast<int>(std::ceil(streak)) + 1, 2, 32);
    image = cv::Mat::zeros(camera_.height, camera_.width, CV_32F);
    for (int k = 0; k < renders; ++k) {
      const double tk = t + exposure * frame_interval * ((k + 0.5) / renders - 0.5);
      image += radiance(T_world_camera_at, tk, effects.rolling_shutter);
    }
    image /= renders;
  } else {
    image = radiance(T_world_camera_at, t, effects.rolling_shutter);
  }
  if (effects.lens_blur > 0) {
    // A real lens never images an edge as sharply as the pixel grid: without this blur, sub-pixel
    // corner refinement with small windows errs by up to 0.1 px on the perfectly sharp edges.
    cv::GaussianBlur(image, image, cv::Size(), effects.lens_blur, effects.lens_blur, cv::BORDER_REPLICATE);
  }
  if (effects.illumination > 0) {
    // Slow, smooth brightness drift (clouds, auto-exposure): two incommensurate periods.
    const double gain = 1.0 + effects.illumination * (0.7 * std::sin(2 * M_PI * t / 23.0) +
                                                      0.3 * std::sin(2 * M_PI * t / 7.3 + 1.0));
    image *= gain;
  }
  if (effects.noise_sigma > 0) {
    cv::RNG rng(seed * 0x9E3779B97F4A7C15ull + static_cast<std::uint64_t>(frame_index) + 1);
    cv::Mat noise(image.size(), CV_32F);
    rng.fill(noise, cv::RNG::NORMAL, 0.0, effects.noise_sigma);
    image += noise;
  }
  cv::Mat out;
  image.convertTo(out, CV_8U);  // rounds and saturates
  return out;
}

}  // namespace slamcmp
