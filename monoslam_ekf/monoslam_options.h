#pragma once
// The MonoSLAM back-end's options: the EKF's pieces (ekf/ekf_options.h) and the board detector.
#include "core/chessboard.h"
#include "core/options.h"
#include "ekf/ekf_options.h"
#include "ekf/ekf_slam.h"
#include "monoslam_ekf/two_view_orientation.h"
#include "tracking/board_presence.h"

namespace slamcmp {

struct MonoslamOptions {
  EkfSlamOptions filter;  // listed flat: motion, search, feature_init, inverse_depth, ransac, map, health, reporting
  StartOptions start;
  RelocalisationOptions relocalisation;
  ChessboardDetectorOptions board;
  BoardPresenceOptions board_presence;
  TwoViewOrientationOptions two_view_orientation;
  template <class V>
  void visit(V& v) {
    visitFilterOptions(v, filter);
    v("start", start, "first camera state uncertainty");
    v("relocalisation", relocalisation, "--init none: lost frames relocalised against the map");
    v("board", board, "chessboard detection (initialisation and re-initialisation)");
    v("board_presence", board_presence,
      "the quick test (X-junctions) before each search for the board once it has been seen (restarts after a "
      "divergence search every frame)");
    v("two_view_orientation", two_view_orientation,
      "--init none: the orientation measured by two-view geometry to each of the last frames, on tracks of its own");
  }
  void check() const {}  // each field's struct checks itself (checkOptions)
};

}  // namespace slamcmp
