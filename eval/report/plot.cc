#include "eval/report/plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "core/interrupt.h"

namespace slamcmp {

std::string shadeColour(const std::string& colour, double t) {
  unsigned r = 0, g = 0, b = 0;
  if (colour.size() != 7 || std::sscanf(colour.c_str(), "#%02x%02x%02x", &r, &g, &b) != 3) return colour;
  // A colour too dark to darken (monoslam's black) is lightened for every t, by 0.45 + 0.3 t: its
  // variants then differ from it and from each other (darkened, they were all black).
  if (std::max({r, g, b}) < 0x40) t = 0.45 + 0.3 * t;
  auto mix = [t](unsigned c) { return static_cast<unsigned>(t > 0 ? c + (255 - c) * t : c * (1 + t)); };
  char out[8];
  std::snprintf(out, sizeof out, "#%02x%02x%02x", mix(r), mix(g), mix(b));
  return out;
}

namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// numpy's default quantile (linear between the nearest ranks) of a non-empty sample.
double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  const double h = q * static_cast<double>(v.size() - 1);
  const size_t lo = static_cast<size_t>(std::floor(h)), hi = std::min(v.size() - 1, lo + 1);
  return v[lo] + (h - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

}  // namespace

std::string gnuplotScript(const Figure& figure, const std::string& png_path) {
  const int rows = (static_cast<int>(figure.panels.size()) + figure.columns - 1) / figure.columns;
  const int height = rows * figure.panel_height_px + (figure.title.empty() ? 0 : 40);
  std::ostringstream s;
  s.precision(10);
  // Data first, as inline datablocks; a blank line breaks a line at each NaN. Stacked bars are
  // drawn as bars from 0 to the running sum, the tallest first, so that each shows its own segment.
  std::vector<PlotPanel> panels = figure.panels;
  for (PlotPanel& panel : panels)
    for (size_t k = 1; panel.stacked_bars && k < panel.series.size(); ++k)
      for (size_t i = 0; i < panel.series[k].y.size() && i < panel.series[k - 1].y.size(); ++i)
        panel.series[k].y[i] = (std::isfinite(panel.series[k].y[i]) ? panel.series[k].y[i] : 0.0) +
                               (std::isfinite(panel.series[k - 1].y[i]) ? panel.series[k - 1].y[i] : 0.0);
  for (size_t p = 0; p < panels.size(); ++p)
    for (size_t k = 0; k < panels[p].series.size(); ++k) {
      const PlotSeries& ser = panels[p].series[k];
      if (!ser.point_labels.empty()) {
        s << "$l" << p << "_" << k << " << EOD\n";
        for (size_t i = 0; i < ser.x.size() && i < ser.y.size() && i < ser.point_labels.size(); ++i)
          if (std::isfinite(ser.x[i]) && std::isfinite(ser.y[i]))
            s << ser.x[i] << " " << ser.y[i] << " " << quoted(ser.point_labels[i]) << "\n";
        s << "EOD\n";
      }
      s << "$d" << p << "_" << k << " << EOD\n";
      if (ser.boxplot) {  // one row: x, first quartile, min, max, third quartile, median
        std::vector<double> v;
        for (double y : ser.y)
          if (std::isfinite(y)) v.push_back(y);
        if (!v.empty() && !ser.x.empty())
          s << ser.x.front() << " " << quantile(v, 0.25) << " " << quantile(v, 0) << " " << quantile(v, 1) << " "
            << quantile(v, 0.75) << " " << quantile(v, 0.5) << "\n";
        s << "EOD\n";
        continue;
      }
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
  for (size_t p = 0; p < panels.size(); ++p) {
    const PlotPanel& panel = panels[p];
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
    if (!panel.xtics.empty()) {
      s << "set xtics (";
      for (size_t i = 0; i < panel.xtics.size(); ++i)
        s << (i ? ", " : "") << quoted(panel.xtics[i].second) << " " << panel.xtics[i].first;
      s << ") rotate by -30 left\nset boxwidth 0.5 absolute\nset xrange [" << panel.xtics.front().first - 0.6 << ":"
        << panel.xtics.back().first + 0.6 << "]\nset yrange [0:*]\n";
    } else {
      s << "set xtics autofreq norotate\n";
    }
    if (panel.series.empty()) {
      s << "set key off\nplot NaN notitle\nset key\n";
      continue;
    }
    s << "plot ";
    for (size_t n = 0; n < panel.series.size(); ++n) {
      const size_t k = panel.stacked_bars ? panel.series.size() - 1 - n : n;
      const PlotSeries& ser = panel.series[k];
      if (n) s << ", \\\n     ";
      if (panel.stacked_bars) {
        s << "$d" << p << "_" << k << " using 1:2:(0.6) with boxes fs solid 0.85 border lc rgb '#555555' fc rgb "
          << quoted(ser.color) << " title " << quoted(ser.label);
        continue;
      }
      if (ser.boxplot) {  // gnuplot's own boxplot draws no box under 4 values: quartile boxes, min-max whiskers
        s << "$d" << p << "_" << k << " using 1:2:3:4:5 with candlesticks whiskerbars 0.5 lc rgb " << quoted(ser.color)
          << " fs solid 0.35 border lc rgb " << quoted(ser.color) << " title " << quoted(ser.label)
          << ", \\\n     $d" << p << "_" << k << " using 1:6:6:6:6 with candlesticks lc rgb " << quoted(ser.color)
          << " lw 2 notitle";
        continue;
      }
      if (ser.points && !ser.colour_by.empty()) {
        s << "$d" << p << "_" << k << " using 1:2:3 with points pt 7 ps 0.6 lc palette title " << quoted(ser.label);
        continue;
      }
      s << "$d" << p << "_" << k << " using 1:2 with " << (ser.points ? "points pt 7 ps 0.4" : "lines")
        << " lc rgb " << quoted(ser.color) << " lw " << ser.width << (ser.dashed ? " dt 2" : " dt 1")
        << " title " << quoted(ser.label);
      if (!ser.point_labels.empty())
        s << ", \\\n     $l" << p << "_" << k << " using 1:2:3 with labels offset char 0.8,0.6 left font ',8' tc rgb "
          << quoted(ser.color) << " notitle";
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
  // A terminal's Ctrl-C reaches gnuplot too: that is the interruption, not a missing gnuplot.
  if (status != 0 && interruptRequested()) throw Interrupted("interrupted while drawing " + path);
  if (status != 0) throw std::runtime_error("gnuplot failed writing " + path + " (is gnuplot installed?)");
}

}  // namespace slamcmp
