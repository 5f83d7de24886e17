#pragma once
// A rolling shutter reads the image row by row (CameraModel::rowTime: the middle row at the frame's
// time), while the camera moves on. The filter's state is the
// camera at the frame's time; with its constant velocities it predicts where each feature is when
// its row is read, searches there, and takes the match back to the frame's time by the same shift
// (the measurement model stays the frame-time projection: the shift's dependence on the velocities
// is neither in the search ellipse nor in the update, so the velocities learn nothing from it).
// Depth-particle rays (a board-started monoslam's new features) and hybrid's board corners and
// tracked points are compared as read. A hand-held camera turning 1 rad/s with a 30 ms readout moves a
// feature up to 8 px between its frame-time and row-time images: a filter that ignores it turns
// 5 % too far (docs/findings.md, session 29).
#include <Eigen/Core>

#include "core/camera.h"
#include "core/geometry.h"
#include "ekf/map_feature.h"

namespace slamcmp {

// Where `feature` appears in a rolling-shutter image minus where the camera at the frame's time
// (x's) sees it at uv_frame_time: its prediction at its row's time under the constant velocities
// of x, the row found by two fixed-point steps. Zero with readout 0 or where it cannot be predicted.
Vec2 rollingShutterShift(const CameraModel& camera, double readout, const Eigen::VectorXd& x,
                         const MapFeature& feature, const Vec2& uv_frame_time);

// The pixel where the camera at the frame's time sees the ray that the rolling-shutter image shows
// at uv: the camera's turn (w_camera, rad/s, camera frame) over the row's time undone. Its
// translation is neglected (a new feature's depth is unknown; at 1 m and 0.1 m/s it moves 1.5 mm).
Vec2 pixelAtFrameTime(const CameraModel& camera, double readout, const Vec3& w_camera, const Vec2& uv);

}  // namespace slamcmp
