#pragma once
// The MonoSLAM back-end's options: the EKF's pieces (ekf/ekf_options.h) and the board detector.
#include "core/chessboard.h"
#include "core/options.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

struct MonoslamOptions {
  MotionModelOptions motion;
  ActiveSearchOptions search;
  FeatureInitOptions feature_init;
  MapManagementOptions map;
  HealthOptions health;
  ReportingOptions reporting;
  StartOptions start;
  ChessboardDetectorOptions board;
  template <class V>
  void visit(V& v) {
    v("motion", motion, "constant-velocity motion model");
    v("search", search, "active search");
    v("feature_init", feature_init, "new features: rays with depth particles");
    v("map", map, "map size and deletion");
    v("health", health, "divergence detection");
    v("reporting", reporting, "when frames are reported lost instead of extrapolated");
    v("start", start, "first camera state uncertainty");
    v("board", board, "chessboard detection (initialisation and re-initialisation)");
  }
  void check() const {}  // each field's struct checks itself (checkOptions)
};

}  // namespace slamcmp
