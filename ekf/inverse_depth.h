#pragma once
// Inverse-depth features (Civera, Davison and Montiel, T-RO 2008): y = (x0, theta, phi, rho) with
// x0 the centre of the camera that first saw the feature, m(theta, phi) = (cos(phi) sin(theta),
// -sin(phi), cos(phi) cos(theta)) the world-frame direction of its ray and rho the inverse of its
// depth along m; the point is x0 + m / rho. A feature starts in one frame at any depth (infinity
// included: rho = 0), is measured from then on, and becomes a 3D point (3 state values instead of
// 6) once the linearity index says the Euclidean form is as linear.
#include <vector>

#include <Eigen/Core>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "ekf/measurement_model.h"

namespace slamcmp {

using Vec6 = Eigen::Matrix<double, 6, 1>;

// m(theta, phi), with d m / d(theta, phi).
Vec3 inverseDepthDirection(double theta, double phi, Eigen::Matrix<double, 3, 2>* J = nullptr);

// The feature's Euclidean point x0 + m / rho (rho clamped to min_rho: a feature at infinity is
// given a far point, for its template warp and the overlay).
Vec3 inverseDepthPoint(const Vec6& y, double min_rho = 1e-3);

// h = project(R(q)^T (rho (x0 - r) + m)) (the point scaled by rho, which the
// projection ignores, so rho = 0 is a point at infinity), with H_r, H_q and the 2x6 H_y. False when
// the scaled point is not in front of the camera.
bool predictInverseDepthMeasurement(const CameraModel& camera, const Vec3& r, const Vec4& q, const Vec6& y,
                                    PointMeasurement* out);

// The feature seen at the distorted pixel uv from the current camera: x0 = r, (theta, phi) of the
// ray, rho = rho0; its covariance from the camera's (r, q), the pixel noise and rho_sigma.
StateBlock inverseDepthFeature(const EkfState& state, const CameraModel& camera, const Vec2& uv_distorted,
                               double pixel_sigma, double rho0, double rho_sigma);
// That feature appended to the map (before the state's tail). Returns its state offset, or -1 (the
// state unchanged) for a ray so near the world's vertical axis that its azimuth theta is undefined
// (a standard deviation of a radian or more).
int appendInverseDepthFeature(EkfState& state, const CameraModel& camera, const Vec2& uv_distorted,
                              double pixel_sigma, double rho0, double rho_sigma);

// Civera eq. 15: L_d = 4 sigma_d / d1 |cos(alpha)|, sigma_d = sigma_rho / rho^2, d1 the distance
// from the camera centre r to the point and alpha the angle between m and that line of sight.
// Infinite for rho <= 0 and where it is undefined (the camera centre on the point).
double linearityIndex(const EkfState& state, int offset);

// The Euclidean point x0 + m / rho and its Jacobian d p / d y (3x6).
Vec3 inverseDepthToPoint(const Vec6& y, Eigen::Matrix<double, 3, 6>* J);

// The scale gauge of a map started without a target: a pseudo-measurement that the mean inverse
// depth of the features at `offsets` is rho0, with noise sigma^2 (a rank-1 update: the images
// cannot see the map's scale, but its depths' ratios stay theirs to estimate). Features still at
// their prior rho0 do not move. False, the state untouched, for no features, or for sigma 0 with
// their inverse depths already certain (S not positive definite).
bool constrainMeanInverseDepth(EkfState& state, const std::vector<int>& offsets, double rho0, double sigma);

// Replaces the feature at `offset` by its point (covariance J P J^T, cross covariances J P_y,rest).
// Its 6 rows are removed, the point appended at the end; returns the point's offset.
int convertToPoint(EkfState& state, int offset);

}  // namespace slamcmp
