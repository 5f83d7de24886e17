#pragma once
// A textured plane z = plane_z (world) seen through a camera model: exact images for the patch
// tests, with no dependency on the sequence renderer.
#include <opencv2/core.hpp>

#include "core/camera.h"

namespace slamcmp::test {

// Smooth, non-repetitive grey texture on the plane (world X, Y in metres), 0..255.
double planeTexture(double X, double Y);

// The plane z = plane_z as the camera at T_world_camera sees it (CV_8U, camera.width x height;
// pixels whose ray misses the plane are 0).
cv::Mat renderPlane(const CameraModel& camera, const SE3& T_world_camera, double plane_z);

// A 640x480 camera with mild distortion.
CameraModel testCamera();

// The plane z = 0 seen by testCamera() from 1.6 m (T_world_camera0) and 0.15 m to the side of it
// (T_world_camera1), rendered once for the tests that use them (a render takes 0.15 s).
extern const SE3 kT_world_camera0, kT_world_camera1;
const cv::Mat& planeView0();
const cv::Mat& planeView1();

}  // namespace slamcmp::test
