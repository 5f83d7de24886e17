#pragma once
// Hartley's normalisation for the linear (DLT, 8-point) solvers: conditions the system so the
// solution does not depend on where the coordinates' origin and scale happen to be.
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

// The similarity T moving the points' centroid to the origin and their mean distance to sqrt(2).
Mat3 hartleyNormalisation(const std::vector<Vec2>& points);

}  // namespace slamcmp
