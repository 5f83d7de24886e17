// OverlayDrawer on hand-built FrameOverlays: each primitive is drawn in its colour where the
// overlay puts it, the 3-sigma ellipse has the size S gives, and the status and legend are drawn
// even when the back-end filled no overlay.
#include "eval/overlay/overlay_drawing.h"

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

constexpr uint8_t kGrey = 128;

Frame greyFrame(int width = 640, int height = 480, int index = 7) {
  Frame f;
  f.index = index;
  f.timestamp = 0.7;
  f.grey = cv::Mat(height, width, CV_8UC1, cv::Scalar(kGrey));
  return f;
}

cv::Vec3b bgr(const cv::Scalar& s) {
  return {static_cast<uint8_t>(s[0]), static_cast<uint8_t>(s[1]), static_cast<uint8_t>(s[2])};
}
cv::Vec3b at(const cv::Mat& image, const Vec2& uv) {
  return image.at<cv::Vec3b>(static_cast<int>(std::lround(uv.y())), static_cast<int>(std::lround(uv.x())));
}
bool untouched(const cv::Vec3b& c) { return c == cv::Vec3b(kGrey, kGrey, kGrey); }

// Largest per-channel difference to `colour` among the pixels within `radius` of `uv`.
int nearestColourError(const cv::Mat& image, const Vec2& uv, const cv::Scalar& colour, int radius) {
  int best = 255;
  const cv::Vec3b want = bgr(colour);
  for (int dy = -radius; dy <= radius; ++dy)
    for (int dx = -radius; dx <= radius; ++dx) {
      const cv::Vec3b c = at(image, uv + Vec2(dx, dy));
      int err = 0;
      for (int k = 0; k < 3; ++k) err = std::max(err, std::abs(c[k] - want[k]));
      best = std::min(best, err);
    }
  return best;
}

FrameResult resultWith(FrameOverlay overlay, const std::string& source = "board") {
  FrameResult r;
  r.status = TrackStatus::Tracked;
  r.source = source;
  r.T_world_camera = SE3();
  r.overlay = std::move(overlay);
  return r;
}

TEST(OverlayDrawing, BoardCornersAndAxesInTheirColoursAtTheirPixels) {
  FrameOverlay o;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 4; ++i) o.board_corners.push_back({10 * j + i, Vec2(300.3 + 30 * i, 200.6 + 30 * j)});
  o.board_axes = {Vec2(300.3, 200.6), Vec2(360.2, 200.6), Vec2(300.3, 260.1), Vec2(280.0, 150.0)};
  OverlayDrawer drawer;
  std::vector<DrawnPrimitive> drawn;
  const cv::Mat image = drawer.draw(greyFrame(), resultWith(o), &drawn);
  ASSERT_EQ(image.type(), CV_8UC3);
  ASSERT_EQ(image.size(), cv::Size(640, 480));
  for (const OverlayBoardCorner& c : o.board_corners)
    EXPECT_EQ(at(image, c.uv), bgr(overlay_colour::kBoardCorner)) << c.uv.transpose();
  // Along each axis, half way from the origin (away from the corner markers' arms for y and z).
  EXPECT_LE(nearestColourError(image, Vec2(300.3, 215), overlay_colour::kAxisY, 1), 40);
  EXPECT_LE(nearestColourError(image, Vec2(290.2, 175.3), overlay_colour::kAxisZ, 1), 40);
  EXPECT_LE(nearestColourError(image, Vec2(345.0, 200.6), overlay_colour::kAxisX, 1), 40);

  int corners = 0, axes = 0;
  for (const auto& d : drawn) {
    if (d.kind == "board_corner") {
      // Listed by the target's own index (here 10 j + i), not by their place in the list.
      EXPECT_EQ(d.uv, o.board_corners.at(4 * (d.id / 10) + d.id % 10).uv) << d.id;
      EXPECT_EQ(d.state, "detected");
      ++corners;
    } else if (d.kind == "board_axis") {
      EXPECT_EQ(d.uv, o.board_axes.at(d.id));
      ++axes;
    }
  }
  EXPECT_EQ(corners, 12);
  EXPECT_EQ(axes, 4);
}

// A lost frame's axes would draw the pose its back-end rejected (monoslam's extrapolation when its
// position std passed 3 cm): its search is drawn, the axes are not, in the image or overlay.csv.
TEST(OverlayDrawing, ALostFrameDrawsNoAxes) {
  FrameOverlay o;
  o.board_axes = {Vec2(300.3, 200.6), Vec2(360.2, 200.6), Vec2(300.3, 260.1), Vec2(280.0, 150.0)};
  o.features = {{1, Vec2(100.2, 150.4), OverlayFeatureState::Failed}};
  FrameResult lost = resultWith(o, "ekf");
  lost.status = TrackStatus::Lost;
  lost.T_world_camera.reset();
  OverlayDrawer drawer;
  std::vector<DrawnPrimitive> drawn;
  const cv::Mat image = drawer.draw(greyFrame(), lost, &drawn);
  ASSERT_EQ(drawn.size(), 1u);
  EXPECT_EQ(drawn[0].kind, "feature");
  EXPECT_TRUE(untouched(at(image, Vec2(345.0, 200.6))));  // half way along x
  EXPECT_TRUE(untouched(at(image, Vec2(300.3, 215))));    // and y
  // The same overlay with the pose: drawn.
  drawer.draw(greyFrame(), resultWith(o, "ekf"), &drawn);
  EXPECT_EQ(drawn.size(), 5u);
}

TEST(OverlayDrawing, FeatureStatesInTheirColours) {
  FrameOverlay o;
  o.patch_size = 11;
  o.features = {{1, Vec2(100.2, 150.4), OverlayFeatureState::Inlier},
                {2, Vec2(160.0, 150.0), OverlayFeatureState::Rejected},
                {3, Vec2(220.0, 150.0), OverlayFeatureState::Matched},
                {4, Vec2(280.0, 150.0), OverlayFeatureState::Failed},
                {5, Vec2(340.0, 150.0), OverlayFeatureState::Unmeasured},
                {6, Vec2(400.0, 150.0), OverlayFeatureState::Initialising}};
  OverlayDrawer drawer;
  std::vector<DrawnPrimitive> drawn;
  const cv::Mat image = drawer.draw(greyFrame(), resultWith(o, "ekf"), &drawn);
  EXPECT_EQ(at(image, o.features[1].uv), bgr(overlay_colour::kRejected));
  EXPECT_EQ(at(image, o.features[5].uv), bgr(overlay_colour::kInitialising));
  // Patches: an outline one pixel outside the 11x11 patch (half size 5), which stays untouched.
  EXPECT_EQ(at(image, o.features[2].uv + Vec2(-6, 0)), bgr(overlay_colour::kMatched));
  EXPECT_EQ(at(image, o.features[2].uv + Vec2(6, 3)), bgr(overlay_colour::kMatched));
  EXPECT_TRUE(untouched(at(image, o.features[2].uv + Vec2(-5, 0))));
  EXPECT_EQ(at(image, o.features[3].uv + Vec2(0, -6)), bgr(overlay_colour::kFailed));
  EXPECT_TRUE(untouched(at(image, o.features[3].uv)));
  // Inliers and unmeasured features: rings, hollow.
  EXPECT_EQ(nearestColourError(image, o.features[0].uv, overlay_colour::kInlier, 4), 0);
  EXPECT_TRUE(untouched(at(image, o.features[0].uv)));
  EXPECT_EQ(nearestColourError(image, o.features[4].uv, overlay_colour::kUnmeasured, 4), 0);
  EXPECT_TRUE(untouched(at(image, o.features[4].uv)));

  ASSERT_EQ(drawn.size(), o.features.size());
  for (size_t i = 0; i < drawn.size(); ++i) {
    EXPECT_EQ(drawn[i].kind, "feature");
    EXPECT_EQ(drawn[i].id, o.features[i].id);
    EXPECT_EQ(drawn[i].uv, o.features[i].uv);
    EXPECT_EQ(drawn[i].state, toString(o.features[i].state));
  }
}

// S = R diag(100, 25) R^T, R a 30 degree turn: semi-axes 3 * 10 = 30 px and 3 * 5 = 15 px.
TEST(OverlayDrawing, SearchEllipseIsThreeSigmaOfS) {
  const double a = 30 * M_PI / 180;
  Mat2 R;
  R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
  const Vec2 centre(320.4, 240.2);
  FrameOverlay o;
  o.search_ellipses = {{9, centre, R * Vec2(100, 25).asDiagonal() * R.transpose(), true},
                       {10, Vec2(500, 300), Mat2::Identity() * 16, false}};
  OverlayDrawer drawer;
  std::vector<DrawnPrimitive> drawn;
  const cv::Mat image = drawer.draw(greyFrame(), resultWith(o, "ekf"), &drawn);
  const Vec2 major = R.col(0), minor = R.col(1);
  // On the curve (anti-aliased: some pixel within 1 px holds the colour to within a few levels).
  EXPECT_LE(nearestColourError(image, centre + 30 * major, overlay_colour::kMatched, 1), 40);
  EXPECT_LE(nearestColourError(image, centre - 30 * major, overlay_colour::kMatched, 1), 40);
  EXPECT_LE(nearestColourError(image, centre + 15 * minor, overlay_colour::kMatched, 1), 40);
  // Inside and outside, untouched.
  EXPECT_TRUE(untouched(at(image, centre + 25 * major)));
  EXPECT_TRUE(untouched(at(image, centre + 35 * major)));
  EXPECT_TRUE(untouched(at(image, centre + 11 * minor)));
  EXPECT_TRUE(untouched(at(image, centre + 19 * minor)));
  // The failed search: a 12 px circle in yellow.
  EXPECT_LE(nearestColourError(image, Vec2(512, 300), overlay_colour::kFailed, 1), 40);
  ASSERT_EQ(drawn.size(), 2u);
  EXPECT_EQ(drawn[0].state, "matched");
  EXPECT_EQ(drawn[1].state, "failed");
  EXPECT_EQ(drawn[1].id, 10);
}

TEST(OverlayDrawing, ParticleLineJoinsTheParticles) {
  FrameOverlay o;
  o.particle_lines = {{Vec2(100, 300), Vec2(150, 300), Vec2(200, 320)}};
  OverlayDrawer drawer;
  std::vector<DrawnPrimitive> drawn;
  const cv::Mat image = drawer.draw(greyFrame(), resultWith(o, "ekf"), &drawn);
  EXPECT_LE(nearestColourError(image, Vec2(125, 300), overlay_colour::kInitialising, 1), 40);
  EXPECT_LE(nearestColourError(image, Vec2(175, 310), overlay_colour::kInitialising, 1), 40);
  EXPECT_TRUE(untouched(at(image, Vec2(150, 310))));
  ASSERT_EQ(drawn.size(), 2u);
  EXPECT_EQ(drawn[0].uv, Vec2(100, 300));
  EXPECT_EQ(drawn[0].state, "near");
  EXPECT_EQ(drawn[1].uv, Vec2(200, 320));
  EXPECT_EQ(drawn[1].state, "far");
}

// Rows (top) or columns changed from the plain grey frame in a band of the image.
int changedRows(const cv::Mat& image, int from, int to) {
  int rows = 0;
  for (int y = from; y < to; ++y)
    for (int x = 0; x < image.cols; ++x)
      if (!untouched(image.at<cv::Vec3b>(y, x))) {
        ++rows;
        break;
      }
  return rows;
}

TEST(OverlayDrawing, StatusDrawnWithoutOverlayAndLegendOnceSomethingWasDrawn) {
  OverlayDrawer drawer;
  FrameResult lost;
  lost.reason = std::string("the board left the image and too few features remain; ") + std::string(200, 'x');
  std::vector<DrawnPrimitive> drawn{{"stale", 0, Vec2::Zero(), ""}};
  const cv::Mat first = drawer.draw(greyFrame(), lost, &drawn);
  EXPECT_TRUE(drawn.empty());
  EXPECT_GT(changedRows(first, 0, 100), 20);     // status panel: three lines of text
  EXPECT_EQ(changedRows(first, 240, 480), 0);    // no legend yet, nothing else drawn
  // The lost reason is in the lost colour (red) somewhere on its line, and does not overflow.
  bool red = false;
  for (int y = 0; y < 100 && !red; ++y)
    for (int x = 0; x < first.cols && !red; ++x) {
      const cv::Vec3b c = first.at<cv::Vec3b>(y, x);
      red = c[2] > 200 && c[1] < 90 && c[0] < 90;
    }
  EXPECT_TRUE(red);

  FrameOverlay o;
  o.features = {{1, Vec2(600, 50), OverlayFeatureState::Inlier}};
  drawer.draw(greyFrame(), resultWith(o));
  // The legend stays once an entry was seen, even on a frame without an overlay.
  const cv::Mat later = drawer.draw(greyFrame(), FrameResult{});
  EXPECT_GT(changedRows(later, 400, 480), 10);
}

TEST(OverlayDrawing, TextGrowsWithTheImage) {
  OverlayDrawer small_drawer, large_drawer;
  const cv::Mat small = small_drawer.draw(greyFrame(640, 480), FrameResult{});
  const cv::Mat large = large_drawer.draw(greyFrame(1280, 720), FrameResult{});
  const int small_rows = changedRows(small, 0, 200), large_rows = changedRows(large, 0, 300);
  EXPECT_GT(large_rows, small_rows * 1.3);
  EXPECT_LT(large_rows, small_rows * 1.7);
}

TEST(OverlayDrawing, NonFinitePositionsAreSkipped) {
  FrameOverlay o;
  o.features = {{1, Vec2(NAN, 3), OverlayFeatureState::Inlier}, {2, Vec2(1e12, 3), OverlayFeatureState::Matched}};
  o.board_corners = {{0, Vec2(INFINITY, 1)}};
  o.search_ellipses = {{3, Vec2(100, 100), Mat2::Zero(), true}};
  o.particle_lines = {{Vec2(NAN, NAN)}};
  OverlayDrawer drawer;
  std::vector<DrawnPrimitive> drawn;
  drawer.draw(greyFrame(), resultWith(o), &drawn);
  EXPECT_TRUE(drawn.empty());
}

}  // namespace
}  // namespace slamcmp
