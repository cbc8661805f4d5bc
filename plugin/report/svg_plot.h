// A small, dependency-free SVG line-plot writer: a figure is a grid of
// panels, each with axes (ticks, labels, optional log-y or equal aspect) and
// series drawn as lines and/or markers; one legend (with an optional title)
// lists every series label of the figure. The output is a
// self-contained SVG document (also embeddable inline in HTML). No I/O: the
// caller writes the string.
//
//   PlotFigure figure;
//   figure.title = "RMSE vs odometry rotation noise";
//   PlotPanel& panel = figure.panels.emplace_back();
//   panel.title = "(a) rotation";
//   panel.x_label = "noise SD [rad]";
//   panel.y_label = "RMSE [deg]";
//   panel.series.push_back({"ALSP", {0, 0.1}, {0.2, 0.5}});
//   const std::string svg = RenderSvg(figure);
//
// Non-finite y values (and, with log_y, non-positive ones) break the line.
#pragma once

#include <string>
#include <vector>

namespace odomcal {

enum class MarkerShape { kCircle, kSquare, kTriangle, kDiamond };

struct PlotSeries {
  std::string label;
  std::vector<double> x;
  std::vector<double> y;
  std::string color;    // CSS colour; empty: DefaultSeriesColor(index)
  bool dashed = false;  // e.g. batch-refined variants
  bool markers = true;  // a marker per point
  bool line = true;     // points joined by a line
  MarkerShape marker_shape = MarkerShape::kCircle;
  double marker_radius_px = 2.5;
};

// Text at a data point (e.g. a name beside a marker), over the series. A
// label that would overlap one drawn before it in its panel moves up or
// down by a line; it is kept inside the plot area. Not in the legend, and
// it does not widen the axes.
struct PlotLabel {
  double x = 0.0;  // data units
  double y = 0.0;
  std::string text;
  std::string color;  // CSS colour; empty: #222
  // The text's anchor relative to the point, pixels (y down).
  double dx_px = 0.0;
  double dy_px = 0.0;
  enum class Anchor { kStart, kMiddle, kEnd } anchor = Anchor::kStart;
  bool bold = false;
};

struct PlotPanel {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_y = false;
  // The same pixels per unit on x and y (a map): the shorter data range is
  // padded about its centre, never stretched. Ignores log_y.
  bool equal_aspect = false;
  std::vector<PlotSeries> series;
  std::vector<PlotLabel> labels;
};

struct PlotFigure {
  std::string title;
  std::vector<PlotPanel> panels;
  int num_columns = 2;
  double panel_width_px = 440.0;
  double panel_height_px = 300.0;
  bool legend = true;
  std::string legend_title;  // e.g. "Pair in the calibration:"
};

// The SVG document.
std::string RenderSvg(const PlotFigure& figure);

// `text` with & < > " written as entities, for SVG and HTML text and
// attribute values.
std::string EscapeMarkup(const std::string& text);

// A qualitative palette, repeating after 10 colours.
std::string DefaultSeriesColor(int index);

// An upper bound of the width `text` (UTF-8) takes at font_size_px in
// Helvetica, Arial or Liberation Sans: for laying out legends without
// overlaps whatever font the viewer picks among these.
double TextWidthUpperBoundPx(const std::string& text, double font_size_px);

// "Nice" tick positions covering [min, max] (about target_count of them, at
// 1, 2 or 5 times a power of ten); with log_scale, powers of ten (plus 2 and
// 5 times them when the range spans less than two decades).
std::vector<double> AxisTicks(double min,
                              double max,
                              int target_count,
                              bool log_scale);

}  // namespace odomcal
