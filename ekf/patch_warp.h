#pragma once
// A feature's appearance: a crop of the image where it was first seen, warped to the current view
// by the homography of a small plane through the feature facing that first camera (Davison et al.
// 2007, section 3.7), so the 11x11 template follows scale, rotation and perspective changes.
#include <optional>

#include <opencv2/core.hpp>

#include "core/camera.h"

namespace slamcmp {

struct PatchSource {
  cv::Mat crop;          // CV_8U, a square crop of the first image around the feature
  Vec2 crop_origin;      // pixel of crop(0, 0) in that image
  Vec2 uv0;              // where the feature was first seen (distorted pixels)
  SE3 T_world_camera0;   // the camera that first saw it
  std::optional<Vec3> normal_world;  // a known surface normal (the board's); else the plane faces camera 0
};

// The crop of `grey` (crop_size, odd) centred on the nearest pixel to uv; false if it leaves the image.
bool makePatchSource(const cv::Mat& grey, const Vec2& uv, int crop_size, const SE3& T_world_camera0,
                     PatchSource* source);

// The size x size template at the first view (unwarped), CV_32F; false if it leaves the crop.
bool sourceTemplate(const PatchSource& source, int size, cv::Mat* templ);

// The template as a camera at T_world_camera should see the feature at y_world around its predicted
// pixel: each template pixel's ray meets the plane through y_world facing camera 0 and is projected
// into the first image. The map is linearised at the centre (an affine warp, exact to well under a
// pixel across 11x11 pixels) and anchored at uv0, so errors in y_world or in the first pose change
// only the template's shape, never its centre. False if the plane is seen edge-on or the warp
// leaves the crop.
bool warpTemplate(const PatchSource& source, const CameraModel& camera, const SE3& T_world_camera,
                  const Vec3& y_world, const Vec2& uv_predicted, int size, cv::Mat* templ);

}  // namespace slamcmp
