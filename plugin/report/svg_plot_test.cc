#include "odomcal/plugin/report/svg_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {
namespace {

void ExpectTicks(const std::vector<double>& ticks,
                 const std::vector<double>& expected) {
  ASSERT_EQ(ticks.size(), expected.size());
  for (size_t k = 0; k < ticks.size(); ++k) {
    EXPECT_NEAR(ticks[k], expected[k], 1e-9 * std::abs(expected[k]) + 1e-12)
        << k;
  }
}

PlotSeries Series(const std::string& label,
                  std::vector<double> x,
                  std::vector<double> y) {
  PlotSeries series;
  series.label = label;
  series.x = std::move(x);
  series.y = std::move(y);
  return series;
}

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// The numbers of every `<path d="...">` of the SVG, one vector per path, and
// how many subpaths ("M") each has.
struct SvgPath {
  std::vector<double> numbers;
  int num_moves = 0;
};

std::vector<SvgPath> Paths(const std::string& svg) {
  std::vector<SvgPath> paths;
  const std::regex path_regex("<path d=\"([^\"]*)\"");
  for (std::sregex_iterator it(svg.begin(), svg.end(), path_regex), end;
       it != end;
       ++it) {
    SvgPath path;
    const std::string d = (*it)[1];
    for (const char c : d) path.num_moves += c == 'M';
    const std::regex number("-?[0-9.]+");
    for (std::sregex_iterator n(d.begin(), d.end(), number); n != end; ++n) {
      path.numbers.push_back(std::stod(n->str()));
    }
    paths.push_back(path);
  }
  return paths;
}

TEST(AxisTicks, LinearTicksAreNiceStepsCoveringTheRange) {
  ExpectTicks(AxisTicks(0.0, 1.0, 6, false), {0.0, 0.2, 0.4, 0.6, 0.8, 1.0});
  ExpectTicks(AxisTicks(-3.0, 7.0, 6, false), {-2.0, 0.0, 2.0, 4.0, 6.0});
  ExpectTicks(AxisTicks(0.013, 0.051, 6, false), {0.02, 0.03, 0.04, 0.05});
  ExpectTicks(AxisTicks(-1.0, 1.0, 3, false), {-1.0, 0.0, 1.0});
  EXPECT_EQ(AxisTicks(-1.0, 1.0, 3, false)[1], 0.0);  // exactly 0, not 1e-17
}

TEST(AxisTicks, LogTicksArePowersOfTenAndFinerOverLessThanTwoDecades) {
  ExpectTicks(AxisTicks(1.0, 1000.0, 6, true), {1.0, 10.0, 100.0, 1000.0});
  ExpectTicks(AxisTicks(1.0, 10.0, 6, true), {1.0, 2.0, 5.0, 10.0});
}

TEST(AxisTicks, EmptyOrInvalidRangesGiveNoTicks) {
  EXPECT_TRUE(AxisTicks(1.0, 1.0, 6, false).empty());
  EXPECT_TRUE(AxisTicks(2.0, 1.0, 6, false).empty());
  EXPECT_TRUE(AxisTicks(0.0, 10.0, 6, true).empty());
  EXPECT_TRUE(AxisTicks(0.0, std::nan(""), 6, false).empty());
}

// A wide path (10 m by 2 m) in a nearly square panel: with equal_aspect one
// metre is as many pixels on x as on y; without, y is stretched.
TEST(RenderSvg, EqualAspectGivesTheSamePixelsPerMetreOnBothAxes) {
  for (const bool equal_aspect : {true, false}) {
    PlotFigure figure;
    PlotPanel& panel = figure.panels.emplace_back();
    panel.equal_aspect = equal_aspect;
    panel.series.push_back(Series("path", {0.0, 10.0, 10.0}, {0.0, 0.0, 2.0}));
    const std::vector<SvgPath> paths = Paths(RenderSvg(figure));
    ASSERT_EQ(paths.size(), 1u);
    const std::vector<double>& p = paths[0].numbers;  // x0 y0 x1 y1 x2 y2
    ASSERT_EQ(p.size(), 6u);
    const double px_per_m_x = (p[2] - p[0]) / 10.0;
    const double px_per_m_y = (p[3] - p[5]) / 2.0;  // SVG y grows downwards
    if (equal_aspect) {
      EXPECT_NEAR(px_per_m_x, px_per_m_y, 0.01 * px_per_m_x);
    } else {
      EXPECT_GT(px_per_m_y, 2.0 * px_per_m_x);
    }
  }
}

TEST(RenderSvg,
     EqualAspectPadsTheShorterRangeAboutItsCentreAndTicksBothAxesAlike) {
  PlotFigure figure;
  PlotPanel& panel = figure.panels.emplace_back();
  panel.equal_aspect = true;
  panel.series.push_back(Series("path", {0.0, 10.0}, {5.0, 7.0}));
  const std::string svg = RenderSvg(figure);
  auto ticks = [&](const std::string& axis) {
    std::vector<double> values;
    const std::regex tick("class=\"" + axis + "-tick\"[^>]*>([^<]*)<");
    for (std::sregex_iterator it(svg.begin(), svg.end(), tick), end; it != end;
         ++it) {
      values.push_back(std::stod((*it)[1]));
    }
    return values;
  };
  const std::vector<double> x = ticks("x"), y = ticks("y");
  ASSERT_GE(x.size(), 3u);
  ASSERT_GE(y.size(), 3u);
  EXPECT_DOUBLE_EQ(x[1] - x[0], y[1] - y[0]);  // square grid cells
  // y is padded about 6 m, the middle of the data, to 228 px of the 364 px
  // that x's 11 m (with padding) take: 6.9 m, ticks 4, 6, 8.
  EXPECT_EQ(y, (std::vector<double>{4.0, 6.0, 8.0}));
  EXPECT_EQ(x.front(), 0.0);
  EXPECT_EQ(x.back(), 10.0);
}

TEST(RenderSvg, NonFiniteValuesBreakTheLine) {
  PlotFigure figure;
  PlotPanel& panel = figure.panels.emplace_back();
  const double nan = std::nan(""),
               inf = std::numeric_limits<double>::infinity();
  panel.series.push_back(
      Series("a", {0, 1, 2, 3, 4, 5, 6}, {1, 2, nan, 3, 4, inf, 5}));
  panel.series.push_back(Series("b", {0, nan, 2}, {1, 1, 1}));
  const std::vector<SvgPath> paths = Paths(RenderSvg(figure));
  ASSERT_EQ(paths.size(), 2u);
  EXPECT_EQ(paths[0].num_moves, 3);
  EXPECT_EQ(paths[0].numbers.size(), 2u * 5u);  // the five finite points
  EXPECT_EQ(paths[1].num_moves, 2);
}

TEST(RenderSvg, TextIsEscaped) {
  PlotFigure figure;
  figure.title = "a<b & c>d";
  figure.legend_title = "<legend>";
  PlotPanel& panel = figure.panels.emplace_back();
  panel.title = "\"quoted\"";
  panel.x_label = "x<1";
  panel.series.push_back(Series("s&p", {0, 1}, {0, 1}));
  const std::string svg = RenderSvg(figure);
  EXPECT_TRUE(Contains(svg, ">a&lt;b &amp; c&gt;d<"));
  EXPECT_TRUE(Contains(svg, ">&lt;legend&gt;<"));
  EXPECT_TRUE(Contains(svg, ">&quot;quoted&quot;<"));
  EXPECT_TRUE(Contains(svg, ">x&lt;1<"));
  EXPECT_TRUE(Contains(svg, ">s&amp;p<"));
  EXPECT_FALSE(Contains(svg, "a<b"));
  EXPECT_FALSE(Contains(svg, "s&p"));
}

TEST(TextWidthUpperBoundPx, GrowsWithTheTextAndCountsCodePointsNotBytes) {
  EXPECT_EQ(TextWidthUpperBoundPx("", 12.0), 0.0);
  EXPECT_GT(TextWidthUpperBoundPx("WWW", 12.0),
            TextWidthUpperBoundPx("iii", 12.0));
  // Helvetica's widest glyphs: "W" 0.944 em, "m" 0.833 em, digits 0.556 em.
  EXPECT_GE(TextWidthUpperBoundPx("W", 10.0), 9.44);
  EXPECT_GE(TextWidthUpperBoundPx("m", 10.0), 8.33);
  EXPECT_GE(TextWidthUpperBoundPx("0", 10.0), 5.56);
  // "θ" is two bytes, one glyph.
  EXPECT_EQ(TextWidthUpperBoundPx("\u03b8", 10.0), 10.0);
}

// Legend entries of many long labels: each label starts after its swatch,
// and no two entries of a row overlap or leave the figure.
TEST(RenderSvg, LegendEntriesDoNotOverlap) {
  PlotFigure figure;
  figure.num_columns = 1;
  figure.panel_width_px = 500;
  figure.legend_title = "Pair in the calibration:";
  PlotPanel& panel = figure.panels.emplace_back();
  const std::vector<std::string> labels = {
      "odometry (robot base)",
      "camera centres, sub-model 0_0",
      "W",
      "MMMMMMMMMMMMMMMM",
      "not used (outlier or left out)",
      "in a stretch rejected as contradicting",
      "end",
      "\u03b8\u03b8\u03b8\u03b8\u03b8\u03b8"};
  for (const std::string& label : labels) {
    PlotSeries series = Series(label, {0, 1}, {0, 1});
    series.markers = label.size() % 2 == 0 || label == "end";
    series.line = label != "end";
    panel.series.push_back(series);
  }
  const std::string svg = RenderSvg(figure);
  struct Box {
    double left, right, y;
  };
  std::vector<Box> boxes;
  const std::regex entry(
      "<g class=\"legend-entry\">\n<(line x1|circle cx)=\"([0-9.]+)\"[\\s\\S]*?"
      "<text class=\"legend-label\" x=\"([0-9.]+)\" "
      "y=\"([0-9.]+)\"[^>]*>([^<]*)</text>");
  for (std::sregex_iterator it(svg.begin(), svg.end(), entry), end; it != end;
       ++it) {
    const double swatch_left = std::stod((*it)[2]);
    const double label_x = std::stod((*it)[3]);
    const std::string label = (*it)[5];
    const double swatch_right =
        (*it)[1] == "line x1" ? swatch_left + 26.0 : swatch_left + 5.0;
    EXPECT_GE(label_x, swatch_right + 4.0) << label;
    boxes.push_back({std::min(swatch_left, label_x - 32.0),
                     label_x + TextWidthUpperBoundPx(label, 12.0),
                     std::stod((*it)[4])});
  }
  ASSERT_EQ(boxes.size(), labels.size()) << svg;
  std::smatch title;
  ASSERT_TRUE(std::regex_search(
      svg,
      title,
      std::regex("class=\"legend-title\" x=\"([0-9.]+)\" y=\"([0-9.]+)\"")));
  boxes.push_back(
      {std::stod(title[1]),
       std::stod(title[1]) + TextWidthUpperBoundPx(figure.legend_title, 12.0),
       std::stod(title[2])});
  int rows = 0;
  for (size_t a = 0; a < boxes.size(); ++a) {
    EXPECT_GE(boxes[a].left, 0.0);
    EXPECT_LE(boxes[a].right, 500.0);
    for (size_t b = a + 1; b < boxes.size(); ++b) {
      if (boxes[a].y != boxes[b].y) continue;
      EXPECT_TRUE(boxes[a].right <= boxes[b].left ||
                  boxes[b].right <= boxes[a].left)
          << a << " and " << b << " overlap";
    }
    rows += a == 0 || boxes[a].y != boxes[a - 1].y;
  }
  EXPECT_GE(rows, 3);  // the labels needed wrapping
}

TEST(RenderSvg, MarkerShapesAreDrawnAndMarkerOnlySeriesHaveNoPath) {
  PlotFigure figure;
  PlotPanel& panel = figure.panels.emplace_back();
  PlotSeries start = Series("start", {0}, {0});
  start.line = false;
  start.marker_shape = MarkerShape::kSquare;
  PlotSeries end = Series("end", {1}, {1});
  end.line = false;
  end.marker_shape = MarkerShape::kTriangle;
  panel.series = {start, end};
  const std::string svg = RenderSvg(figure);
  EXPECT_TRUE(Paths(svg).empty());
  EXPECT_TRUE(Contains(svg, "<rect x="));
  EXPECT_TRUE(Contains(svg, "<polygon points="));
}

// Labels at one point move apart by whole lines; a label near the edge stays
// inside the plot area; a label at a non-finite point is left out.
TEST(RenderSvg, PointLabelsDoNotOverlapAndStayInsideThePlot) {
  PlotFigure figure;
  figure.num_columns = 1;
  figure.panel_width_px = 400;
  figure.panel_height_px = 300;
  PlotPanel& panel = figure.panels.emplace_back();
  panel.series.push_back(Series("data", {0, 10}, {0, 10}));
  for (const char* text : {"front <a>", "rear", "right"}) {
    PlotLabel label;
    label.x = 5.0;
    label.y = 5.0;
    label.text = text;
    panel.labels.push_back(label);
  }
  PlotLabel edge;
  edge.x = 10.0;
  edge.y = 10.0;
  edge.text = "a long label at the corner";
  edge.anchor = PlotLabel::Anchor::kStart;
  panel.labels.push_back(edge);
  PlotLabel nowhere;
  nowhere.x = std::nan("");
  nowhere.text = "nowhere";
  panel.labels.push_back(nowhere);
  const std::string svg = RenderSvg(figure);
  EXPECT_TRUE(Contains(svg, ">front &lt;a&gt;</text>"));
  EXPECT_FALSE(Contains(svg, "nowhere"));
  const std::regex label_regex(
      "class=\"plot-label\" x=\"([0-9.]+)\" y=\"([0-9.]+)\"[^>]*>([^<]*)<");
  struct Box {
    double left, right, baseline;
  };
  std::vector<Box> boxes;
  for (std::sregex_iterator it(svg.begin(), svg.end(), label_regex), end;
       it != end;
       ++it) {
    const double x = std::stod((*it)[1]);
    boxes.push_back(
        {x, x + TextWidthUpperBoundPx((*it)[3], 12.0), std::stod((*it)[2])});
  }
  ASSERT_EQ(boxes.size(), 4u) << svg;
  for (size_t a = 0; a < boxes.size(); ++a) {
    // The plot area: x 62 .. 386, y 28 .. 256 (the panel's margins).
    EXPECT_GE(boxes[a].left, 62.0) << a;
    EXPECT_LE(boxes[a].right, 386.0) << a;
    EXPECT_GE(boxes[a].baseline - 10.0, 28.0) << a;
    EXPECT_LE(boxes[a].baseline + 3.0, 256.0) << a;
    for (size_t b = a + 1; b < boxes.size(); ++b) {
      const bool apart_x =
          boxes[a].right <= boxes[b].left || boxes[b].right <= boxes[a].left;
      const bool apart_y =
          std::abs(boxes[a].baseline - boxes[b].baseline) >= 13.0;
      EXPECT_TRUE(apart_x || apart_y) << a << " and " << b << " overlap";
    }
  }
  // The first stays where it was asked to be; the next two a line above and
  // below it.
  EXPECT_NEAR(boxes[1].baseline, boxes[0].baseline - 14.0, 1e-9);
  EXPECT_NEAR(boxes[2].baseline, boxes[0].baseline + 14.0, 1e-9);
}

}  // namespace
}  // namespace odomcal
