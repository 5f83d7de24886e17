#include "ekf/patch_warp.h"

#include <cmath>

#include "core/image.h"

namespace slamcmp {

namespace {

// Samples `size` x `size` pixels at centre + a * dx + b * dy of the crop, dx, dy in [-half, half].
bool sampleAffine(const PatchSource& source, const Vec2& centre, const Vec2& a, const Vec2& b, int size,
                  cv::Mat* templ) {
  const int half = size / 2;
  templ->create(size, size, CV_32F);
  for (int dy = -half; dy <= half; ++dy) {
    float* row = templ->ptr<float>(dy + half);
    for (int dx = -half; dx <= half; ++dx) {
      const Vec2 uv = centre + a * dx + b * dy - source.crop_origin;
      double value;
      if (!sampleBilinear(source.crop, uv.x(), uv.y(), &value)) return false;
      row[dx + half] = static_cast<float>(value);
    }
  }
  return true;
}

}  // namespace

bool makePatchSource(const cv::Mat& grey, const Vec2& uv, int crop_size, const SE3& T_world_camera0,
                     PatchSource* source) {
  const int half = crop_size / 2;
  const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
  if (u - half < 0 || v - half < 0 || u + half >= grey.cols || v + half >= grey.rows) return false;
  source->crop = grey(cv::Rect(u - half, v - half, crop_size, crop_size)).clone();
  source->crop_origin = Vec2(u - half, v - half);
  source->uv0 = uv;
  source->T_world_camera0 = T_world_camera0;
  return true;
}

bool sourceTemplate(const PatchSource& source, int size, cv::Mat* templ) {
  return sampleAffine(source, source.uv0, Vec2(1, 0), Vec2(0, 1), size, templ);
}

bool warpTemplate(const PatchSource& source, const CameraModel& camera, const SE3& T_world_camera,
                  const Vec3& y_world, const Vec2& uv_predicted, int size, cv::Mat* templ) {
  const Vec3 c0 = source.T_world_camera0.t();
  const Vec3 normal = source.normal_world ? *source.normal_world : (c0 - y_world).normalized();
  const SE3 T_camera0_world = source.T_world_camera0.inverse();
  bool ok = true;
  // Current pixel -> ray -> plane -> first image (distorted pixels).
  auto toSource = [&](const Vec2& uv) -> Vec2 {
    const Vec2 xy = camera.undistortPixel(uv);
    const Vec3 dir = T_world_camera.R() * Vec3(xy.x(), xy.y(), 1.0);
    const double denom = normal.dot(dir);
    if (std::abs(denom) < 1e-6 * dir.norm()) {
      ok = false;
      return Vec2::Zero();
    }
    const double s = normal.dot(y_world - T_world_camera.t()) / denom;
    const Vec3 p_camera0 = T_camera0_world * (T_world_camera.t() + s * dir);
    if (s <= 0 || p_camera0.z() <= 1e-6) {
      ok = false;
      return Vec2::Zero();
    }
    return camera.project(p_camera0);
  };
  const double step = 0.5 * (size / 2);  // central differences over half the template
  // The template is centred on where the feature was first seen, whatever the estimates of y and
  // of the first pose say; the geometry gives only the local shape of the warp.
  const Vec2 a = (toSource(uv_predicted + Vec2(step, 0)) - toSource(uv_predicted - Vec2(step, 0))) / (2 * step);
  const Vec2 b = (toSource(uv_predicted + Vec2(0, step)) - toSource(uv_predicted - Vec2(0, step))) / (2 * step);
  if (!ok || !a.allFinite() || !b.allFinite()) return false;
  return sampleAffine(source, source.uv0, a, b, size, templ);
}

}  // namespace slamcmp
