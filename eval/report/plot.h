#pragma once
// Figures as PNG through gnuplot (pngcairo): axes, ticks, labels, legends, several panels.
#include <string>
#include <utility>
#include <vector>

namespace slamcmp {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  // NaN in y breaks the line (a lost stretch)
  std::string color = "black";  // any gnuplot colour name or "#rrggbb"
  bool dashed = false;
  bool points = false;  // points instead of a line
  double width = 1.5;
  std::vector<double> colour_by{};  // non-empty (with points): each point coloured by this value
                                    // through the panel's colour bar instead of `color`
  bool fits_range = true;         // false: not counted when an equal-axes panel fits its range
  bool boxplot = false;           // a box plot of the y values at x (x constant: one box)
  std::vector<std::string> point_labels{};  // non-empty: each point labelled with this text
};

struct PlotPanel {
  std::string title, xlabel, ylabel;
  std::vector<PlotSeries> series;
  bool equal_axes = false;  // same scale on x and y (trajectory views)
  bool log_y = false;
  bool reverse_y = false;      // y grows downwards (the world's Y axis points down)
  double colour_max = 0;       // > 0: colour bar from 0 to this (values above it take its colour)
  std::string colour_label{};  // the colour bar's label
  std::vector<std::pair<double, std::string>> xtics{};  // non-empty: named categories at these x
  bool stacked_bars = false;   // each series a segment of bars stacked at the xtics, in series order
};

struct Figure {
  std::string title;
  std::vector<PlotPanel> panels;
  int columns = 1;  // panels are laid out row by row
  int width_px = 1100;
  int panel_height_px = 330;
};

// Writes `figure` to `path` (PNG). Throws std::runtime_error when gnuplot is missing or fails.
void writeFigurePng(const Figure& figure, const std::string& path);
// The gnuplot script writeFigurePng runs (for tests and for users who want to restyle a figure).
std::string gnuplotScript(const Figure& figure, const std::string& png_path);

// "#rrggbb" mixed towards white (t > 0) or black (t < 0) by |t| (other colours as they are): the
// variants of one method (its settings, its start) in shades of its colour. A colour too dark to
// darken (every channel under 0x40) is mixed towards white by 0.45 + 0.3 t instead.
std::string shadeColour(const std::string& colour, double t);

}  // namespace slamcmp
