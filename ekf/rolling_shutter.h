#pragma once
// A rolling shutter reads the image row by row (CameraModel::rowTime: the middle row at the frame's
// time), while the camera moves on; a hand-held camera turning 1 rad/s with a 30 ms readout moves a
// feature up to 8 px between its frame-time and row-time images, and a filter that ignores it
// turns 5 % too far (docs/findings.md, session 29). The filter's state is the camera at the
// frame's time, and its constant velocities say where the camera is when a row is read:
// - the map's patch features (1 px) are searched where that puts them and the match is taken back
//   to the frame's time by the same shift (rollingShutterShift; the update stays the frame-time
//   projection, so the velocities learn nothing from it);
// - hybrid's board corners (0.01 px) and tracked points are predicted at their rows' times, with
//   the velocities in their Jacobians (predictAtRowTime): a shift taken back with the velocities
//   held would carry the velocities' error, 80 times the corners' noise;
// - new features' pixels, and the pixels of hybrid's tracks in its window, are turned back to the
//   frame's time by the camera's turn alone (pixelAtFrameTime).
// Depth-particle rays (a board-started monoslam's new features) are compared as read.
#include <functional>

#include <Eigen/Core>

#include "core/camera.h"
#include "core/geometry.h"
#include "ekf/map_feature.h"
#include "ekf/measurement_model.h"
#include "ekf/motion_model.h"

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

// How far (pixels, std) a feature read at the first or last row may be from where the constant
// velocities put it: the motion model's angular velocity is a random walk (white angular
// acceleration, variance sigma_alpha^2 / reference_rate per second), whose turn over half the
// readout has variance q (readout / 2)^3 / 3, seen through the mean focal length. Its translation
// is left out (it depends on the depth). About 0.3 px for sigma_alpha 3 rad/s^2 at 30 Hz, 525 px
// and a 30 ms readout, 0.1 px at sigma_alpha 1.
double rollingShutterPixelSigma(const CameraModel& camera, double readout, const MotionModelOptions& motion);

// A known world point where a rolling-shutter image shows it: seen from the camera at its row's
// time under the constant velocities of x_camera (the row found by fixed-point steps to 1e-4 px),
// with h's Jacobians with respect to the whole camera block (H_v, H_w; row_timed set), the row's
// own dependence on the state included. Readout 0: predictMeasurement at the frame's time. False
// where it cannot be predicted (closer than min_depth).
bool predictAtRowTime(const CameraModel& camera, double readout, const CameraVector& x_camera, const Vec3& p_world,
                      PointMeasurement* h, double min_depth);

// The same for any point a camera pose predicts: predict(r, q, h) fills h (with H_r, H_q, H_y) as
// seen from the camera at (r, q), false where it cannot (an inverse-depth point, hybrid's tracked
// points: ekf/inverse_depth.h).
using PredictFromPose = std::function<bool(const Vec3& r, const Vec4& q, PointMeasurement* h)>;
bool predictAtRowTime(const CameraModel& camera, double readout, const CameraVector& x_camera,
                      const PredictFromPose& predict, PointMeasurement* h);

}  // namespace slamcmp
