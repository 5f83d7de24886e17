#include "eval/report/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

namespace slamcmp {

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

std::string gnuplotScript(const Figure& figure, const std::string& png_path) {
  const int rows = (static_cast<int>(figure.panels.size()) + figure.columns - 1) / figure.columns;
  const int height = rows * figure.panel_height_px + (figure.title.empty() ? 0 : 40);
  std::ostringstream s;
  s.precision(10);
  // Data first, as inline datablocks; a blank line breaks a line at each NaN.
  for (size_t p = 0; p < figure.panels.size(); ++p)
    for (size_t k = 0; k < figure.panels[p].series.size(); ++k) {
      const PlotSeries& ser = figure.panels[p].series[k];
      s << "$d" << p << "_" << k << " << EOD\n";
      bool gap = false;
      const bool coloured = !ser.colour_by.empty();
      for (size_t i = 0; i < ser.x.size() && i < ser.y.size(); ++i) {
        if (!std::isfinite(ser.x[i]) || !std::isfinite(ser.y[i]) ||
            (coloured && (i >= ser.colour_by.size() || !std::isfinite(ser.colour_by[i])))) {
          if (!gap) s << "\n";
          gap = true;
          continue;
        }
        gap = false;
        s << ser.x[i] << " " << ser.y[i];
        if (coloured) s << " " << ser.colour_by[i];
        s << "\n";
      }
      s << "EOD\n";
    }
  s << "set terminal pngcairo noenhanced size " << figure.width_px << "," << height
    << " font 'DejaVu Sans,10' linewidth 1\n";
  s << "set output " << quoted(png_path) << "\n";
  s << "set grid lc rgb '#dddddd'\nset tics out nomirror\n";
  // viridis: ordered in lightness, readable in grey and by colour-blind readers.
  s << "set palette defined (0 '#440154', 0.25 '#3b528b', 0.5 '#21918c', 0.75 '#5ec962', 1 '#fde725')\n";
  s << "set multiplot layout " << rows << "," << figure.columns;
  // An empty second line keeps the title clear of keys placed above the top row's panels.
  if (!figure.title.empty()) s << " title " << quoted(figure.title) << ".\"\\n\" font ',13'";
  s << "\n";
  for (size_t p = 0; p < figure.panels.size(); ++p) {
    const PlotPanel& panel = figure.panels[p];
    s << "set title " << quoted(panel.title) << "\n";
    s << "set xlabel " << quoted(panel.xlabel) << "\nset ylabel " << quoted(panel.ylabel) << "\n";
    if (panel.colour_max > 0) {
      // The colour bar takes the right, the key goes on top in one short row (three rows met the
      // figure's title).
      s << "set key outside top center horizontal box opaque\nset colorbox\n"
        << "set cbrange [0:" << panel.colour_max << "]\nset cblabel " << quoted(panel.colour_label) << "\n";
    } else {
      s << "set key outside right top box opaque\nunset colorbox\n";
    }
    if (panel.equal_axes) {
      // One scale on both axes over a square range around the data, so a flat trajectory stays
      // readable instead of collapsing into a sliver.
      double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
      for (const auto& ser : panel.series)
        for (size_t i = 0; ser.fits_range && i < ser.x.size() && i < ser.y.size(); ++i) {
          if (!std::isfinite(ser.x[i]) || !std::isfinite(ser.y[i])) continue;
          lo[0] = std::min(lo[0], ser.x[i]), hi[0] = std::max(hi[0], ser.x[i]);
          lo[1] = std::min(lo[1], ser.y[i]), hi[1] = std::max(hi[1], ser.y[i]);
        }
      if (lo[0] <= hi[0]) {
        const double half = 0.55 * std::max({hi[0] - lo[0], hi[1] - lo[1], 1e-3});
        const double y_lo = 0.5 * (lo[1] + hi[1]) - half, y_hi = 0.5 * (lo[1] + hi[1]) + half;
        s << "set xrange [" << 0.5 * (lo[0] + hi[0]) - half << ":" << 0.5 * (lo[0] + hi[0]) + half << "]\n"
          << "set yrange [" << (panel.reverse_y ? y_hi : y_lo) << ":" << (panel.reverse_y ? y_lo : y_hi) << "]\n";
      }
      s << "set size ratio -1\n";
    } else {
      s << "set autoscale xy\nset size noratio\nset yrange [*:*] " << (panel.reverse_y ? "reverse" : "noreverse")
        << "\n";
    }
    s << (panel.log_y ? "set logscale y\n" : "unset logscale y\n");
    if (panel.series.empty()) {
      s << "set key off\nplot NaN notitle\nset key\n";
      continue;
    }
    s << "plot ";
    for (size_t k = 0; k < panel.series.size(); ++k) {
      const PlotSeries& ser = panel.series[k];
      if (k) s << ", \\\n     ";
      if (ser.points && !ser.colour_by.empty()) {
        s << "$d" << p << "_" << k << " using 1:2:3 with points pt 7 ps 0.6 lc palette title " << quoted(ser.label);
        continue;
      }
      s << "$d" << p << "_" << k << " using 1:2 with " << (ser.points ? "points pt 7 ps 0.4" : "lines")
        << " lc rgb " << quoted(ser.color) << " lw " << ser.width << (ser.dashed ? " dt 2" : " dt 1")
        << " title " << quoted(ser.label);
    }
    s << "\n";
  }
  s << "unset multiplot\nset output\n";
  return s.str();
}

void writeFigurePng(const Figure& figure, const std::string& path) {
  FILE* gp = popen("gnuplot > /dev/null 2>&1", "w");
  if (!gp) throw std::runtime_error("cannot start gnuplot (install gnuplot-nox)");
  const std::string script = gnuplotScript(figure, path);
  std::fwrite(script.data(), 1, script.size(), gp);
  const int status = pclose(gp);
  if (status != 0) throw std::runtime_error("gnuplot failed writing " + path + " (is gnuplot installed?)");
}

}  // namespace slamcmp
