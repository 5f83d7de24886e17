#pragma once
// A quick test of whether an image region may hold the whole chessboard, run before the detector
// (which costs 100 to 350 ms on a textured frame with no board, most of it grouping the texture's
// quads). A board's inner corners are X-junctions: the ChESS response (Bennett & Lasenby, "ChESS -
// Quick and robust detection of chess-board features", CVIU 2014) is strong there and weak on
// edges, blobs and the corners of isolated shapes. The response is learnt from the board's last
// view (its median over the board's corners), so contrast, lens blur and the squares' size in the
// image set the bar, not a constant.
#include <vector>

#include <opencv2/core.hpp>

#include "core/chessboard.h"
#include "core/target.h"

namespace slamcmp {

struct BoardPresenceOptions {
  bool enabled = true;
  // A pixel is an X-junction when its response (a local maximum) reaches this fraction of the
  // board's median corner response when last seen.
  double response_fraction = 0.4;
  // The region may hold the board when it has at least this fraction of the board's corner count
  // of X-junctions.
  double min_corner_fraction = 0.6;
  template <class V>
  void visit(V& v) {
    v("enabled", enabled,
      "before a search for the whole board, count the X-junctions (ChESS response) and skip the search where "
      "there are too few for the board (only once the board has been seen)");
    v("response_fraction", response_fraction,
      "an X-junction responds at least this fraction of the board's median corner response in its last view");
    v("min_corner_fraction", min_corner_fraction,
      "a region is searched when it has at least this fraction of the board's corner count of X-junctions");
  }
  void check() const;
};

class BoardPresence {
 public:
  explicit BoardPresence(const BoardPresenceOptions& options) : options_(options) {}

  // Learns the board's corner response from a view of its corners `uv` (pixels of `grey`),
  // `spacing` (pixels) apart at the closest.
  void seen(const cv::Mat& grey, const std::vector<cv::Point2f>& uv, double spacing);
  // False when `region` of `grey` has too few X-junctions for `num_corners` board corners; true
  // when it may hold them, or when nothing has been learnt yet (or the test is off).
  bool mayHoldBoard(const cv::Mat& grey, const cv::Rect& region, int num_corners) const;
  bool learnt() const { return reference_response_ > 0; }

 private:
  BoardPresenceOptions options_;
  int radius_ = 5;                   // the ring's radius, pixels: within a square of the last view
  double reference_response_ = -1;   // five times the median corner response in the last view, -1 before any
};

// core's chessboard detector behind the presence test: a region is searched only where it may
// hold the whole board, once a view of the board has been learnt (every board it finds, and every
// view of the whole board given to seen()).
class PresenceGatedDetector {
 public:
  PresenceGatedDetector(const ChessboardTarget& target, const ChessboardDetectorOptions& detector,
                        const BoardPresenceOptions& presence)
      : target_(target), detector_(detector), presence_(presence) {}

  // The whole board in `region` of `grey`: its corners in the whole image's pixels, SPEC order
  // (detectChessboard's); false where none was found or the presence test ruled it out.
  bool detect(const cv::Mat& grey, const cv::Rect& region, std::vector<cv::Point2f>* uv);
  bool detect(const cv::Mat& grey, std::vector<cv::Point2f>* uv) {
    return detect(grey, cv::Rect(0, 0, grey.cols, grey.rows), uv);
  }
  // A view of the whole board found otherwise (tracked corners): learnt from.
  void seen(const cv::Mat& grey, const std::vector<cv::Point2f>& uv);

 private:
  ChessboardTarget target_;
  ChessboardDetectorOptions detector_;
  BoardPresence presence_;
};

// The ChESS response at (x, y) with 16 samples on a ring of `radius` pixels: strong (positive)
// at an X-junction, negative or small on an edge or a blob. (x, y) at least radius + 1 from the
// border.
double chessResponse(const cv::Mat& grey, int x, int y, int radius);

}  // namespace slamcmp
