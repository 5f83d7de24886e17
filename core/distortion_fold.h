#pragma once
// Whether a lens model folds over the image. Past a fold two rays project to one pixel: undistortion
// (Gauss-Newton on distort()) converges to the wrong ray, and the filters' Jacobians point the wrong
// way, so such a model is refused where it is read, and a self-calibration giving one is not used.
#include <string>

#include "core/camera.h"

namespace slamcmp {

// Empty if distort() is one-to-one over the undistorted disc that maps to 1.1x the image's
// farthest corner from the principal point: the radial map r -> r * radial(r) strictly increasing
// with a positive radial factor, and (for the tangential terms) distort()'s Jacobian with a positive
// determinant. Otherwise one phrase saying where it folds, for a message naming the file.
std::string distortionFold(const CameraModel& camera);

}  // namespace slamcmp
