#include "eval/overlay/overlay_drawing.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>

#include <Eigen/Eigenvalues>
#include <opencv2/imgproc.hpp>

namespace slamcmp {

namespace {

constexpr int kShift = 4;  // fractional bits of the sub-pixel coordinates given to OpenCV
constexpr double kSubpixel = 1 << kShift;

// Sizes scale with the image so the drawing reads the same at 640x480 and at 1280x720.
struct Style {
  double s;  // 1 at 480 lines
  int thickness;
  double font_scale;
  int marker;  // half size of markers, pixels

  explicit Style(cv::Size size)
      : s(std::clamp(std::min(size.width, size.height) / 480.0, 0.5, 3.0)),
        thickness(std::max(1, static_cast<int>(std::lround(s)))),
        font_scale(0.5 * s),
        marker(std::max(2, static_cast<int>(std::lround(3 * s)))) {}
};

bool drawable(const Vec2& uv) { return uv.allFinite() && uv.cwiseAbs().maxCoeff() < 1e5; }
cv::Point nearestPixel(const Vec2& uv) { return {static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y()))}; }
cv::Point subpixel(const Vec2& uv) {
  return {static_cast<int>(std::lround(uv.x() * kSubpixel)), static_cast<int>(std::lround(uv.y() * kSubpixel))};
}

enum LegendEntry : unsigned {
  kLegendBoard,
  kLegendAxes,
  kLegendInlier,
  kLegendRejected,
  kLegendMatched,
  kLegendFailed,
  kLegendUnmeasured,
  kLegendInitialising,
  kLegendCount
};

LegendEntry legendEntry(OverlayFeatureState state) {
  switch (state) {
    case OverlayFeatureState::Inlier: return kLegendInlier;
    case OverlayFeatureState::Rejected: return kLegendRejected;
    case OverlayFeatureState::Matched: return kLegendMatched;
    case OverlayFeatureState::Failed: return kLegendFailed;
    case OverlayFeatureState::Unmeasured: return kLegendUnmeasured;
    case OverlayFeatureState::Initialising: return kLegendInitialising;
  }
  return kLegendInlier;
}

// The board axes are the frame's pose: a frame without one (lost, initialising) has none drawn, or
// they would show the pose its back-end rejected (a filter's extrapolation, a diverged state).
bool drawsAxes(const FrameOverlay& o, const FrameResult& result) {
  return result.T_world_camera && o.board_axes.size() == 4 &&
         std::all_of(o.board_axes.begin(), o.board_axes.end(), drawable);
}

// The legend entries for what the frame draws (one bit each).
unsigned legendEntries(const FrameOverlay& o, const FrameResult& result) {
  unsigned bits = 0;
  auto set = [&](LegendEntry e) { bits |= 1u << e; };
  if (!o.board_corners.empty()) set(kLegendBoard);
  if (drawsAxes(o, result)) set(kLegendAxes);
  for (const auto& f : o.features) set(legendEntry(f.state));
  for (const auto& e : o.search_ellipses) set(e.matched ? kLegendMatched : kLegendFailed);
  if (!o.particle_lines.empty()) set(kLegendInitialising);
  return bits;
}

cv::Scalar featureColour(OverlayFeatureState state) {
  switch (state) {
    case OverlayFeatureState::Inlier: return overlay_colour::kInlier;
    case OverlayFeatureState::Rejected: return overlay_colour::kRejected;
    case OverlayFeatureState::Matched: return overlay_colour::kMatched;
    case OverlayFeatureState::Failed: return overlay_colour::kFailed;
    case OverlayFeatureState::Unmeasured: return overlay_colour::kUnmeasured;
    case OverlayFeatureState::Initialising: return overlay_colour::kInitialising;
  }
  return overlay_colour::kInlier;
}

// The marker of one feature state centred on `at` (a whole pixel, so the centre colour is exact).
void drawFeatureMarker(cv::Mat& image, cv::Point at, OverlayFeatureState state, int patch_size, const Style& st) {
  const cv::Scalar colour = featureColour(state);
  switch (state) {
    case OverlayFeatureState::Inlier:  // a ring: board corners tracked as features show through
      cv::circle(image, at, st.marker + 1, colour, 1, cv::LINE_8);
      break;
    case OverlayFeatureState::Rejected:
      cv::drawMarker(image, at, colour, cv::MARKER_TILTED_CROSS, 2 * st.marker + 1, st.thickness, cv::LINE_8);
      break;
    case OverlayFeatureState::Matched:
    case OverlayFeatureState::Failed: {
      // The outline just outside the patch, so the patch itself stays visible.
      const int half = std::max(patch_size, 2 * st.marker + 1) / 2 + 1;
      cv::rectangle(image, at - cv::Point(half, half), at + cv::Point(half, half), colour, 1, cv::LINE_8);
      break;
    }
    case OverlayFeatureState::Unmeasured:
      cv::circle(image, at, st.marker, colour, 1, cv::LINE_8);
      break;
    case OverlayFeatureState::Initialising:
      cv::circle(image, at, std::max(1, st.marker - 1), colour, cv::FILLED, cv::LINE_8);
      break;
  }
}

// The 3-sigma ellipse {x : (x - c)^T S^-1 (x - c) <= 9}: semi-axes 3 sqrt(eigenvalues of S).
bool drawSearchEllipse(cv::Mat& image, const OverlayEllipse& e, const Style& st) {
  if (!drawable(e.centre) || !e.S.allFinite()) return false;
  const Eigen::SelfAdjointEigenSolver<Mat2> eig(0.5 * (e.S + e.S.transpose()));
  if (eig.info() != Eigen::Success || eig.eigenvalues()(0) <= 0) return false;
  const double major = 3 * std::sqrt(eig.eigenvalues()(1)), minor = 3 * std::sqrt(eig.eigenvalues()(0));
  if (major > 1e5) return false;
  const Vec2 axis = eig.eigenvectors().col(1);
  const double angle_deg = std::atan2(axis.y(), axis.x()) * 180 / M_PI;
  const cv::RotatedRect box(cv::Point2f(static_cast<float>(e.centre.x()), static_cast<float>(e.centre.y())),
                            cv::Size2f(static_cast<float>(2 * major), static_cast<float>(2 * minor)),
                            static_cast<float>(angle_deg));
  cv::ellipse(image, box, e.matched ? overlay_colour::kMatched : overlay_colour::kFailed, std::max(1, st.thickness - 1),
              cv::LINE_AA);
  return true;
}

// Text lines on a darkened box with its top-left corner at `origin` (clipped to the image).
struct TextLine {
  std::string text;
  cv::Scalar colour;
};
constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;

int lineHeight(const Style& st) {
  int baseline = 0;
  return static_cast<int>(cv::getTextSize("Ag", kFont, st.font_scale, st.thickness, &baseline).height * 1.9);
}

// Scales the box's brightness by `factor` so white and coloured text reads on any background.
void darken(cv::Mat& image, cv::Rect box, double factor) {
  box &= cv::Rect(0, 0, image.cols, image.rows);
  if (box.area() == 0) return;
  cv::Mat roi = image(box);
  roi.convertTo(roi, -1, factor);
}

// Shortens `text` with "..." until it fits `width` pixels.
std::string fitted(std::string text, int width, const Style& st) {
  int baseline = 0;
  while (text.size() > 4 && cv::getTextSize(text, kFont, st.font_scale, st.thickness, &baseline).width > width)
    text = text.substr(0, text.size() - 4) + "...";
  return text;
}

void drawTextPanel(cv::Mat& image, cv::Point origin, const std::vector<TextLine>& lines, const Style& st) {
  const int h = lineHeight(st), pad = h / 4;
  int baseline = 0, width = 0;
  for (const auto& l : lines) width = std::max(width, cv::getTextSize(l.text, kFont, st.font_scale, st.thickness, &baseline).width);
  darken(image, cv::Rect(origin.x, origin.y, width + 2 * pad, static_cast<int>(lines.size()) * h + pad), 0.35);
  for (size_t i = 0; i < lines.size(); ++i)
    cv::putText(image, lines[i].text, origin + cv::Point(pad, static_cast<int>(i + 1) * h - h / 4), kFont,
                st.font_scale, lines[i].colour, st.thickness, cv::LINE_AA);
}

cv::Scalar statusColour(TrackStatus status) {
  switch (status) {
    case TrackStatus::Tracked: return {0, 255, 0};
    case TrackStatus::Initialising: return {0, 255, 255};
    case TrackStatus::Lost: return {60, 60, 255};  // red, light enough to read on the dark panel
  }
  return {255, 255, 255};
}

void drawStatus(cv::Mat& image, const Frame& frame, const FrameResult& result, const Style& st) {
  char head[96];
  std::snprintf(head, sizeof head, "frame %d   t %.3f s", frame.index, frame.timestamp);
  std::string status = statusLabel(result.status, result.source);
  for (char& c : status) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  status += "   features " + std::to_string(result.features) + "   measured " + std::to_string(result.measured);
  std::vector<TextLine> lines{{head, {255, 255, 255}}, {status, statusColour(result.status)}};
  if (!result.reason.empty())
    lines.push_back({fitted(result.reason, image.cols - lineHeight(st), st), statusColour(result.status)});
  drawTextPanel(image, {0, 0}, lines, st);
}

// The legend's swatch for one entry, centred on `at`.
void drawSwatch(cv::Mat& image, LegendEntry entry, cv::Point at, const Style& st) {
  switch (entry) {
    case kLegendBoard:
      cv::drawMarker(image, at, overlay_colour::kBoardCorner, cv::MARKER_CROSS, 2 * st.marker + 3, st.thickness,
                     cv::LINE_8);
      break;
    case kLegendAxes: {
      const int d = st.marker * 2;
      cv::line(image, at - cv::Point(d, 0), at - cv::Point(d / 3, 0), overlay_colour::kAxisX, st.thickness);
      cv::line(image, at - cv::Point(d / 3, 0), at + cv::Point(d / 3, 0), overlay_colour::kAxisY, st.thickness);
      cv::line(image, at + cv::Point(d / 3, 0), at + cv::Point(d, 0), overlay_colour::kAxisZ, st.thickness);
      break;
    }
    case kLegendInlier: drawFeatureMarker(image, at, OverlayFeatureState::Inlier, 0, st); break;
    case kLegendRejected: drawFeatureMarker(image, at, OverlayFeatureState::Rejected, 0, st); break;
    case kLegendMatched: drawFeatureMarker(image, at, OverlayFeatureState::Matched, 0, st); break;
    case kLegendFailed: drawFeatureMarker(image, at, OverlayFeatureState::Failed, 0, st); break;
    case kLegendUnmeasured: drawFeatureMarker(image, at, OverlayFeatureState::Unmeasured, 0, st); break;
    case kLegendInitialising:
      cv::line(image, at - cv::Point(2 * st.marker, 0), at + cv::Point(2 * st.marker, 0),
               overlay_colour::kInitialising, st.thickness);
      break;
    case kLegendCount: break;
  }
}

const char* legendLabel(LegendEntry entry) {
  switch (entry) {
    case kLegendBoard: return "board corners";
    case kLegendAxes: return "board axes x y z";
    case kLegendInlier: return "tracked (inlier)";
    case kLegendRejected: return "rejected";
    case kLegendMatched: return "matched patch, 3-sigma ellipse";
    case kLegendFailed: return "failed patch, 3-sigma ellipse";
    case kLegendUnmeasured: return "visible, not searched";
    case kLegendInitialising: return "depth particles (initialising)";
    case kLegendCount: break;
  }
  return "";
}

// Smaller and lighter than the status: it is read once, and covers less of the scene.
void drawLegend(cv::Mat& image, unsigned seen, const Style& frame_style) {
  Style st = frame_style;
  st.font_scale *= 0.8;
  std::vector<LegendEntry> entries;
  for (unsigned e = 0; e < kLegendCount; ++e)
    if (seen & (1u << e)) entries.push_back(static_cast<LegendEntry>(e));
  if (entries.empty()) return;
  const int h = lineHeight(st), pad = h / 4, swatch = 5 * st.marker;
  int baseline = 0, width = 0;
  for (const auto e : entries)
    width = std::max(width, cv::getTextSize(legendLabel(e), kFont, st.font_scale, st.thickness, &baseline).width);
  const int height = static_cast<int>(entries.size()) * h + pad;
  const cv::Point origin(0, image.rows - height);
  darken(image, cv::Rect(origin.x, origin.y, width + swatch + 3 * pad, height), 0.5);
  for (size_t i = 0; i < entries.size(); ++i) {
    const int y = origin.y + static_cast<int>(i) * h + h / 2 + pad / 2;
    drawSwatch(image, entries[i], {origin.x + pad + swatch / 2, y}, st);
    cv::putText(image, legendLabel(entries[i]), {origin.x + 2 * pad + swatch, y + h / 4}, kFont, st.font_scale,
                {255, 255, 255}, st.thickness, cv::LINE_AA);
  }
}

}  // namespace

cv::Mat OverlayDrawer::draw(const Frame& frame, const FrameResult& result, std::vector<DrawnPrimitive>* drawn) {
  cv::Mat image;
  cv::cvtColor(frame.grey, image, cv::COLOR_GRAY2BGR);
  const Style st(image.size());
  std::vector<DrawnPrimitive> list;
  if (result.overlay) legend_seen_ |= legendEntries(*result.overlay, result);

  // The panels first: what the back-end saw is drawn over them, never hidden by them.
  drawStatus(image, frame, result, st);
  drawLegend(image, legend_seen_, st);

  if (result.overlay) {
    const FrameOverlay& o = *result.overlay;
    for (size_t i = 0; i < o.particle_lines.size(); ++i) {
      std::vector<cv::Point> line;
      std::vector<Vec2> kept;
      for (const Vec2& uv : o.particle_lines[i])
        if (drawable(uv)) {
          line.push_back(subpixel(uv));
          kept.push_back(uv);
        }
      if (line.empty()) continue;
      cv::polylines(image, line, false, overlay_colour::kInitialising, st.thickness, cv::LINE_AA, kShift);
      list.push_back({"particle_line", static_cast<int>(i), kept.front(), "near"});
      list.push_back({"particle_line", static_cast<int>(i), kept.back(), "far"});
    }
    for (const auto& e : o.search_ellipses)
      if (drawSearchEllipse(image, e, st))
        list.push_back({"ellipse", e.feature_id, e.centre, e.matched ? "matched" : "failed"});
    for (const auto& f : o.features) {
      if (!drawable(f.uv)) continue;
      drawFeatureMarker(image, nearestPixel(f.uv), f.state, o.patch_size, st);
      list.push_back({"feature", f.id, f.uv, toString(f.state)});
    }
    // Axes: origin, then the ends of x, y and z.
    if (drawsAxes(o, result)) {
      const cv::Scalar colours[3] = {overlay_colour::kAxisX, overlay_colour::kAxisY, overlay_colour::kAxisZ};
      const char* names[3] = {"x", "y", "z"};
      list.push_back({"board_axis", 0, o.board_axes[0], "origin"});
      for (int a = 0; a < 3; ++a) {
        cv::line(image, subpixel(o.board_axes[0]), subpixel(o.board_axes[a + 1]), colours[a], st.thickness + 1,
                 cv::LINE_AA, kShift);
        cv::putText(image, names[a], nearestPixel(o.board_axes[a + 1]) + cv::Point(st.marker, -st.marker), kFont,
                    st.font_scale, colours[a], st.thickness, cv::LINE_AA);
        list.push_back({"board_axis", a + 1, o.board_axes[a + 1], names[a]});
      }
    }
    // Corners last: the detection is what the back-end's pose rests on.
    for (const OverlayBoardCorner& c : o.board_corners) {
      if (!drawable(c.uv)) continue;
      cv::drawMarker(image, nearestPixel(c.uv), overlay_colour::kBoardCorner, cv::MARKER_CROSS, 2 * st.marker + 3,
                     st.thickness, cv::LINE_8);
      list.push_back({"board_corner", c.id, c.uv, "detected"});
    }
  }
  if (drawn) *drawn = std::move(list);
  return image;
}

}  // namespace slamcmp
