#include "eval/report/plot.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/interrupt.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

Figure twoPanelFigure() {
  Figure fig;
  fig.title = "test";
  PlotPanel a{"a", "frame", "X [m]", {}, false, false};
  a.series.push_back({"ground truth", {0, 1, 2, 3}, {0.0, 0.1, NAN, 0.3}, "#888888", false, false, 3});
  a.series.push_back({"cslam", {0, 1, 2, 3}, {0.0, 0.11, 0.2, 0.31}});
  PlotPanel b{"b", "X [m]", "Z [m]", {}, true, false};
  b.series.push_back({"monoslam", {0, 1}, {1, 2}});
  fig.panels = {a, b};
  return fig;
}

TEST(Plot, ScriptHoldsEverySeriesAndBreaksLinesAtNaN) {
  const std::string script = gnuplotScript(twoPanelFigure(), "/tmp/x.png");
  EXPECT_NE(script.find("$d0_0 << EOD\n0 0\n1 0.1\n\n3 0.3\nEOD"), std::string::npos) << script;
  EXPECT_NE(script.find("$d0_1"), std::string::npos);
  EXPECT_NE(script.find("$d1_0"), std::string::npos);
  EXPECT_NE(script.find("title \"monoslam\""), std::string::npos);
  EXPECT_NE(script.find("set size ratio -1"), std::string::npos);  // equal axes in panel b
  EXPECT_NE(script.find("multiplot layout 2,1"), std::string::npos);
}

TEST(Plot, QuotesInLabelsAreEscaped) {
  Figure fig;
  fig.panels.push_back({"say \"hi\"", "x", "y", {{"a", {0}, {0}}}, false, false});
  EXPECT_NE(gnuplotScript(fig, "/tmp/x.png").find("\"say \\\"hi\\\"\""), std::string::npos);
}

// A map view: points coloured through the colour bar, an outline left out of the fitted range,
// and Y growing downwards.
TEST(Plot, ColouredPointsOutlineAndReversedY) {
  Figure fig;
  PlotPanel p{"map", "Z [m]", "Y [m]", {}, true, false};
  p.reverse_y = true;
  p.colour_max = 20;
  p.colour_label = "error [mm]";
  PlotSeries outline{"scene", {-5, 5}, {-5, 5}};
  outline.fits_range = false;
  PlotSeries points{"map", {0, 1}, {0, 2}};
  points.points = true;
  points.colour_by = {3, 25};
  p.series = {outline, points};
  fig.panels.push_back(p);
  const std::string script = gnuplotScript(fig, "/tmp/x.png");
  EXPECT_NE(script.find("$d0_1 << EOD\n0 0 3\n1 2 25\nEOD"), std::string::npos) << script;
  EXPECT_NE(script.find("using 1:2:3 with points pt 7 ps 0.6 lc palette"), std::string::npos) << script;
  EXPECT_NE(script.find("set cbrange [0:20]"), std::string::npos) << script;
  EXPECT_NE(script.find("set cblabel \"error [mm]\""), std::string::npos) << script;
  // The range is fitted to the points (y 0..2, half-width 0.55 * 2), not to the outline, and reversed.
  EXPECT_NE(script.find("set yrange [2.1:-0.1]"), std::string::npos) << script;
  EXPECT_NE(script.find("set xrange [-0.6:1.6]"), std::string::npos) << script;
}

// Stacked bars: each series drawn from 0 to the running sum, the tallest first; categories named.
TEST(Plot, StackedBarsAndBoxPlotsOverNamedCategories) {
  Figure fig;
  PlotPanel bars;
  bars.xtics = {{0, "cslam"}, {1, "monoslam"}};
  bars.stacked_bars = true;
  bars.series.push_back({"predict", {0, 1}, {1.0, 2.0}});
  bars.series.push_back({"update", {0, 1}, {0.5, NAN}});
  PlotPanel boxes;
  boxes.xtics = bars.xtics;
  PlotSeries box{"cslam", {0, 0, 0}, {1.0, 1.2, 1.1}};
  box.boxplot = true;
  PlotSeries labelled{"sweep", {2, 3}, {1, 2}};
  labelled.point_labels = {"50", "100"};
  boxes.series = {box, labelled};
  fig.panels = {bars, boxes};
  const std::string script = gnuplotScript(fig, "/tmp/x.png");
  EXPECT_NE(script.find("$d0_1 << EOD\n0 1.5\n1 2\nEOD"), std::string::npos) << script;  // 1 + 0.5; 2 + nothing
  EXPECT_LT(script.find("plot $d0_1 using 1:2:(0.6) with boxes"), script.find("$d0_0 using 1:2:(0.6) with boxes"));
  EXPECT_NE(script.find("set xtics (\"cslam\" 0, \"monoslam\" 1)"), std::string::npos) << script;
  // The box: x, quartiles 1.05 and 1.15, whiskers 1.0 to 1.2, median 1.1.
  EXPECT_NE(script.find("$d1_0 << EOD\n0 1.05 1 1.2 1.15 1.1\nEOD"), std::string::npos) << script;
  EXPECT_NE(script.find("$d1_0 using 1:2:3:4:5 with candlesticks"), std::string::npos) << script;
  EXPECT_NE(script.find("$l1_1 << EOD\n2 1 \"50\"\n3 2 \"100\"\nEOD"), std::string::npos) << script;
  EXPECT_NE(script.find("$l1_1 using 1:2:3 with labels"), std::string::npos) << script;
  test::TempDir tmp;
  writeFigurePng(fig, tmp.file("fig.png"));  // gnuplot takes it
  EXPECT_TRUE(std::ifstream(tmp.file("fig.png")).good());
}

TEST(Plot, WritesAPng) {
  test::TempDir tmp;
  const std::string path = tmp.file("fig.png");
  writeFigurePng(twoPanelFigure(), path);
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, 8);
  ASSERT_TRUE(in) << "no PNG written (is gnuplot installed?)";
  EXPECT_EQ(std::string(magic + 1, 3), "PNG");
}

// gnuplot failing once Ctrl-C was pressed (it gets the terminal's SIGINT too) is the interruption
// (exit 130), not "is gnuplot installed?" (exit 1, compare's report lost).
TEST(Plot, AFailureAfterAnInterruptIsTheInterruption) {
  test::TempDir tmp;
  const std::string unwritable = tmp.file("no/such/folder/fig.png");  // gnuplot fails on it
  try {
    writeFigurePng(twoPanelFigure(), unwritable);
    ADD_FAILURE() << "gnuplot wrote into a missing folder";
  } catch (const Interrupted&) {
    ADD_FAILURE() << "an interruption without Ctrl-C";
  } catch (const std::runtime_error&) {
  }
  // In a child process: the request is the process's, for good.
  EXPECT_EXIT(
      {
        requestInterrupt();
        try {
          writeFigurePng(twoPanelFigure(), unwritable);
        } catch (const Interrupted&) {
          std::exit(0);
        } catch (...) {
        }
        std::exit(1);
      },
      ::testing::ExitedWithCode(0), "");
}

// A method's variants (its settings, its start) in shades of its colour, each its own: a colour
// darkened towards black, or lightened towards white; black itself (monoslam's) lightened for every
// shade, where darkening gave four of six variants the same black.
TEST(Plot, ShadesOfOneColourDifferEvenFromBlack) {
  EXPECT_EQ(shadeColour("#d62728", 0.0), "#d62728");
  EXPECT_EQ(shadeColour("#d62728", 0.5), "#ea9393");
  EXPECT_EQ(shadeColour("#d62728", -0.5), "#6b1314");
  const std::vector<std::string> shades = {shadeColour("#000000", -0.45), shadeColour("#000000", 0.0),
                                           shadeColour("#000000", 0.45)};
  EXPECT_EQ(shades[0], "#505050");
  EXPECT_EQ(shades[2], "#959595");
  for (size_t a = 0; a < shades.size(); ++a) {
    EXPECT_NE(shades[a], "#000000");
    for (size_t b = 0; b < a; ++b) EXPECT_NE(shades[a], shades[b]);
  }
  EXPECT_EQ(shadeColour("red", 0.5), "red");  // a colour name as it is
}

}  // namespace
}  // namespace slamcmp
