#include "ekf/ekf_overlay.h"

#include "ekf/measurement_model.h"

namespace slamcmp {

namespace {

OverlayFeatureState overlayState(SearchOutcome outcome) {
  switch (outcome) {
    case SearchOutcome::Matched: return OverlayFeatureState::Matched;
    case SearchOutcome::Failed: return OverlayFeatureState::Failed;
    case SearchOutcome::Unmeasured: break;
  }
  return OverlayFeatureState::Unmeasured;
}

}  // namespace

FrameOverlay ekfOverlay(const EkfState& state, const std::vector<MapFeature>& features,
                             const FrameMeasurement& measurement, const CameraModel& camera,
                             const ChessboardTarget& target, int patch_size) {
  FrameOverlay overlay;
  overlay.patch_size = patch_size;
  for (const FeatureSearch& s : measurement.features) {
    OverlayFeature f;
    f.id = features[s.index].id;
    f.state = overlayState(s.outcome);
    // In the image as read: a rolling shutter's shift included (zero for the unsearched).
    const Vec2 uv_searched = s.uv_predicted + s.rolling_shift;
    f.uv = s.outcome == SearchOutcome::Matched ? s.uv_matched : uv_searched;
    overlay.features.push_back(f);
    if (s.outcome == SearchOutcome::Unmeasured) continue;
    OverlayEllipse e;
    e.feature_id = f.id;
    e.centre = uv_searched;
    e.S = s.S;
    e.matched = s.outcome == SearchOutcome::Matched;
    overlay.search_ellipses.push_back(e);
  }
  auto project = [&](const Vec3& p_world, Vec2* uv) {
    PointMeasurement m;
    if (!predictMeasurement(camera, state.r(), state.q(), p_world, &m)) return false;
    *uv = m.uv_distorted;
    return true;
  };
  for (const MapFeature& f : features) {
    if (!f.is_ray) continue;
    const Vec3 r0 = state.x().segment<3>(f.offset), h = state.x().segment<3>(f.offset + 3);
    OverlayFeature o;
    o.id = f.id;
    o.state = OverlayFeatureState::Initialising;
    if (project(r0 + f.particles.mean() * h, &o.uv)) overlay.features.push_back(o);
    std::vector<Vec2> line;  // particles are kept in increasing depth
    for (double d : f.particles.depth) {
      Vec2 uv;
      if (project(r0 + d * h, &uv)) line.push_back(uv);
    }
    overlay.particle_lines.push_back(std::move(line));
  }
  overlay.board_axes = boardAxes(camera, target.square_size, state.T_world_camera());
  return overlay;
}

}  // namespace slamcmp
