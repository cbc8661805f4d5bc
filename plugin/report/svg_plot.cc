// Layout: panels on a grid of num_columns, each with a fixed margin for its
// title, tick labels and axis labels; the legend is a row of entries (swatch,
// then label, measured with TextWidthUpperBoundPx) under the grid, wrapped to
// the figure width. Axis ranges come from the finite data (log-y: positive
// data), widened to the outer ticks; an empty or constant range gets a unit
// (or one-decade) span. Equal-aspect panels instead pad the data ranges by
// 5 % and widen the shorter one about its centre until both axes have the
// same units per pixel, with one tick step for both (square grid cells).
// Point labels are placed in order, each moved by whole lines off the ones
// before it. Text is XML-escaped.

#include "odomcal/plugin/report/svg_plot.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <sstream>
#include <tuple>
#include <utility>

namespace odomcal {

std::string EscapeMarkup(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

namespace {

constexpr double kMarginLeft = 62.0;
constexpr double kMarginRight = 14.0;
constexpr double kMarginTop = 28.0;
constexpr double kMarginBottom = 44.0;
constexpr double kFigureTitleHeight = 30.0;
constexpr double kLegendRowHeight = 20.0;
constexpr double kLegendFontPx = 12.0;
constexpr double kLegendLeft = 20.0;
constexpr double kSwatchWidth = 26.0;
constexpr double kSwatchGap = 6.0;  // swatch to its label
constexpr double kEntryGap = 22.0;  // label to the next swatch
constexpr int kTargetTicks = 6;

std::string Number(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.2f", value);
  return buffer;
}

std::string TickLabel(double value) {
  if (value == 0.0) return "0";
  char buffer[32];
  const double magnitude = std::abs(value);
  if (magnitude >= 1e4 || magnitude < 1e-3) {
    std::snprintf(buffer, sizeof(buffer), "%.0e", value);
  } else {
    std::snprintf(buffer, sizeof(buffer), "%.6g", value);
  }
  return buffer;
}

bool Usable(double y, bool log_y) {
  return std::isfinite(y) && (!log_y || y > 0.0);
}

double NiceStep(double range, int target_count) {
  const double raw = range / std::max(1, target_count - 1);
  const double power = std::pow(10.0, std::floor(std::log10(raw)));
  const double fraction = raw / power;
  const double nice = fraction <= 1.0   ? 1.0
                      : fraction <= 2.0 ? 2.0
                      : fraction <= 5.0 ? 5.0
                                        : 10.0;
  return nice * power;
}

struct Axis {
  double min = 0.0, max = 1.0;
  bool log = false;
  std::vector<double> ticks;
  double Fraction(double value) const {
    if (log) {
      return (std::log10(value) - std::log10(min)) /
             (std::log10(max) - std::log10(min));
    }
    return (value - min) / (max - min);
  }
};

Axis MakeAxis(double lo, double hi, bool log_scale) {
  Axis axis;
  axis.log = log_scale;
  if (!(lo <= hi)) {  // no data
    lo = log_scale ? 1.0 : 0.0;
    hi = log_scale ? 10.0 : 1.0;
  }
  if (log_scale) {
    lo = std::pow(10.0, std::floor(std::log10(lo)));
    hi = std::pow(10.0, std::ceil(std::log10(hi)));
    if (hi <= lo) hi = lo * 10.0;
  } else {
    if (hi == lo) {
      const double pad = lo == 0.0 ? 1.0 : 0.5 * std::abs(lo);
      lo -= pad;
      hi += pad;
    }
    const double step = NiceStep(hi - lo, kTargetTicks);
    lo = std::floor(lo / step + 1e-9) * step;
    hi = std::ceil(hi / step - 1e-9) * step;
  }
  axis.min = lo;
  axis.max = hi;
  axis.ticks = AxisTicks(lo, hi, kTargetTicks, log_scale);
  return axis;
}

std::vector<double> TicksWithStep(double min, double max, double step) {
  std::vector<double> ticks;
  for (double value = std::ceil(min / step - 1e-9) * step;
       value <= max + 1e-9 * step;
       value += step) {
    ticks.push_back(std::abs(value) < 1e-12 * step ? 0.0 : value);
  }
  return ticks;
}

// Axes with equal units per pixel; [lo, hi] may be empty (lo > hi).
std::pair<Axis, Axis> EqualAspectAxes(double x_lo,
                                      double x_hi,
                                      double y_lo,
                                      double y_hi,
                                      double width_px,
                                      double height_px) {
  if (!(x_lo <= x_hi) || !(y_lo <= y_hi)) x_lo = y_lo = 0.0, x_hi = y_hi = 1.0;
  double x_range = x_hi - x_lo, y_range = y_hi - y_lo;
  const double pad = 0.05 * std::max(x_range, y_range);
  x_range += 2.0 * pad;
  y_range += 2.0 * pad;
  if (x_range == 0.0) x_range = y_range = 1.0;  // one point
  const double units_per_px = std::max(x_range / width_px, y_range / height_px);
  const double x_centre = 0.5 * (x_lo + x_hi), y_centre = 0.5 * (y_lo + y_hi);
  Axis x_axis, y_axis;
  x_axis.min = x_centre - 0.5 * units_per_px * width_px;
  x_axis.max = x_centre + 0.5 * units_per_px * width_px;
  y_axis.min = y_centre - 0.5 * units_per_px * height_px;
  y_axis.max = y_centre + 0.5 * units_per_px * height_px;
  // The shorter axis gets about kTargetTicks ticks, the longer more.
  const double step = NiceStep(
      std::min(x_axis.max - x_axis.min, y_axis.max - y_axis.min), kTargetTicks);
  x_axis.ticks = TicksWithStep(x_axis.min, x_axis.max, step);
  y_axis.ticks = TicksWithStep(y_axis.min, y_axis.max, step);
  return {x_axis, y_axis};
}

void DrawMarker(MarkerShape shape,
                double x,
                double y,
                double r,
                const std::string& color,
                std::ostringstream* svg) {
  auto polygon = [&](std::initializer_list<std::pair<double, double>> points) {
    *svg << "<polygon points=\"";
    bool first = true;
    for (const auto& [dx, dy] : points) {
      *svg << (first ? "" : " ") << Number(x + dx * r) << ","
           << Number(y + dy * r);
      first = false;
    }
    *svg << "\" fill=\"" << color << "\"/>\n";
  };
  switch (shape) {
    case MarkerShape::kCircle:
      *svg << "<circle cx=\"" << Number(x) << "\" cy=\"" << Number(y)
           << "\" r=\"" << Number(r) << "\" fill=\"" << color << "\"/>\n";
      break;
    case MarkerShape::kSquare:
      *svg << "<rect x=\"" << Number(x - r) << "\" y=\"" << Number(y - r)
           << "\" width=\"" << Number(2 * r) << "\" height=\"" << Number(2 * r)
           << "\" fill=\"" << color << "\"/>\n";
      break;
    case MarkerShape::kTriangle:
      polygon({{0.0, -1.3}, {1.2, 0.9}, {-1.2, 0.9}});
      break;
    case MarkerShape::kDiamond:
      polygon({{0.0, -1.35}, {1.35, 0.0}, {0.0, 1.35}, {-1.35, 0.0}});
      break;
  }
}

struct PixelBox {
  double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
  bool Overlaps(const PixelBox& other) const {
    return left < other.right && other.left < right && top < other.bottom &&
           other.top < bottom;
  }
};

// Each label where asked, else the nearest free place a line (or more) up
// or down; inside `area` either way.
template <typename ToPixelX, typename ToPixelY>
void DrawLabels(const std::vector<PlotLabel>& labels,
                const PixelBox& area,
                const ToPixelX& px,
                const ToPixelY& py,
                std::ostringstream* svg) {
  constexpr double kFontPx = 12.0;
  constexpr double kLinePx = 14.0;
  constexpr double kAscentPx = 10.0, kDescentPx = 3.0;
  std::vector<PixelBox> placed;
  for (const PlotLabel& label : labels) {
    if (!std::isfinite(label.x) || !std::isfinite(label.y)) continue;
    const double width =
        TextWidthUpperBoundPx(label.text, kFontPx) * (label.bold ? 1.1 : 1.0);
    const double shift = label.anchor == PlotLabel::Anchor::kStart ? 0.0
                         : label.anchor == PlotLabel::Anchor::kMiddle
                             ? 0.5 * width
                             : width;
    // The box's left edge and the baseline.
    double x = px(label.x) + label.dx_px - shift;
    x = std::max(area.left + 2.0, std::min(x, area.right - 2.0 - width));
    const double y0 = py(label.y) + label.dy_px;
    auto box_at = [&](double y) {
      const double baseline =
          std::max(area.top + kAscentPx + 2.0,
                   std::min(y, area.bottom - kDescentPx - 2.0));
      return PixelBox{
          x, baseline - kAscentPx, x + width, baseline + kDescentPx};
    };
    PixelBox box = box_at(y0);
    for (int step = 1; step <= 12; ++step) {
      const bool free =
          std::none_of(placed.begin(), placed.end(), [&](const PixelBox& b) {
            return b.Overlaps(box);
          });
      if (free) break;
      // Up, down, two up, two down, ...
      const int lines = (step + 1) / 2;
      const double offset = kLinePx * lines * (step % 2 != 0 ? -1.0 : 1.0);
      box = box_at(y0 + offset);
    }
    placed.push_back(box);
    *svg << "<text class=\"plot-label\" x=\"" << Number(box.left) << "\" y=\""
         << Number(box.bottom - kDescentPx) << "\" font-size=\""
         << Number(kFontPx) << "\""
         << (label.bold ? " font-weight=\"bold\"" : "") << " fill=\""
         << (label.color.empty() ? "#222" : label.color)
         << "\" stroke=\"white\" stroke-width=\"3\" stroke-linejoin=\"round\" "
            "paint-order=\"stroke\">"
         << EscapeMarkup(label.text) << "</text>\n";
  }
}

void RenderPanel(const PlotPanel& panel,
                 const std::vector<std::string>& colors,
                 const std::vector<int>& color_index,
                 double x0,
                 double y0,
                 double width,
                 double height,
                 std::ostringstream* svg) {
  const bool log_y = panel.log_y && !panel.equal_aspect;
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  for (const PlotSeries& series : panel.series) {
    for (size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
      if (!std::isfinite(series.x[k]) || !Usable(series.y[k], log_y)) {
        continue;
      }
      x_lo = std::min(x_lo, series.x[k]);
      x_hi = std::max(x_hi, series.x[k]);
      y_lo = std::min(y_lo, series.y[k]);
      y_hi = std::max(y_hi, series.y[k]);
    }
  }
  const double left = x0 + kMarginLeft;
  const double top = y0 + kMarginTop;
  const double plot_width = width - kMarginLeft - kMarginRight;
  const double plot_height = height - kMarginTop - kMarginBottom;
  Axis x_axis, y_axis;
  if (panel.equal_aspect) {
    std::tie(x_axis, y_axis) =
        EqualAspectAxes(x_lo, x_hi, y_lo, y_hi, plot_width, plot_height);
  } else {
    if (!log_y && y_lo > 0.0) y_lo = 0.0;  // RMSE-like data: from zero
    x_axis = MakeAxis(x_lo, x_hi, false);
    y_axis = MakeAxis(y_lo, y_hi, log_y);
  }
  auto px = [&](double x) { return left + x_axis.Fraction(x) * plot_width; };
  auto py = [&](double y) {
    return top + (1.0 - y_axis.Fraction(y)) * plot_height;
  };

  *svg << "<g>\n";
  *svg << "<text x=\"" << Number(left + plot_width / 2) << "\" y=\""
       << Number(y0 + 18) << "\" text-anchor=\"middle\" font-size=\"13\" "
       << "font-weight=\"bold\">" << EscapeMarkup(panel.title) << "</text>\n";
  *svg << "<rect x=\"" << Number(left) << "\" y=\"" << Number(top)
       << "\" width=\"" << Number(plot_width) << "\" height=\""
       << Number(plot_height) << "\" fill=\"none\" stroke=\"#333\"/>\n";
  for (const double tick : x_axis.ticks) {
    const double x = px(tick);
    *svg << "<line x1=\"" << Number(x) << "\" y1=\"" << Number(top)
         << "\" x2=\"" << Number(x) << "\" y2=\"" << Number(top + plot_height)
         << "\" stroke=\"#e4e4e4\"/>\n";
    *svg << "<line x1=\"" << Number(x) << "\" y1=\""
         << Number(top + plot_height) << "\" x2=\"" << Number(x) << "\" y2=\""
         << Number(top + plot_height + 4) << "\" stroke=\"#333\"/>\n";
    *svg << "<text x=\"" << Number(x) << "\" y=\""
         << Number(top + plot_height + 16)
         << "\" class=\"x-tick\" text-anchor=\"middle\" font-size=\"11\">"
         << TickLabel(tick) << "</text>\n";
  }
  for (const double tick : y_axis.ticks) {
    const double y = py(tick);
    *svg << "<line x1=\"" << Number(left) << "\" y1=\"" << Number(y)
         << "\" x2=\"" << Number(left + plot_width) << "\" y2=\"" << Number(y)
         << "\" stroke=\"#e4e4e4\"/>\n";
    *svg << "<line x1=\"" << Number(left - 4) << "\" y1=\"" << Number(y)
         << "\" x2=\"" << Number(left) << "\" y2=\"" << Number(y)
         << "\" stroke=\"#333\"/>\n";
    *svg << "<text x=\"" << Number(left - 6) << "\" y=\"" << Number(y + 4)
         << "\" class=\"y-tick\" text-anchor=\"end\" font-size=\"11\">"
         << TickLabel(tick) << "</text>\n";
  }
  *svg << "<text x=\"" << Number(left + plot_width / 2) << "\" y=\""
       << Number(y0 + height - 8) << "\" text-anchor=\"middle\" "
       << "font-size=\"12\">" << EscapeMarkup(panel.x_label) << "</text>\n";
  const double label_x = x0 + 14;
  const double label_y = top + plot_height / 2;
  *svg << "<text x=\"" << Number(label_x) << "\" y=\"" << Number(label_y)
       << "\" text-anchor=\"middle\" font-size=\"12\" transform=\"rotate(-90 "
       << Number(label_x) << " " << Number(label_y) << ")\">"
       << EscapeMarkup(panel.y_label + (log_y ? " (log)" : "")) << "</text>\n";

  for (size_t s = 0; s < panel.series.size(); ++s) {
    const PlotSeries& series = panel.series[s];
    const std::string& color = colors[color_index[s]];
    std::string path;
    bool pen_down = false;
    for (size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
      if (!std::isfinite(series.x[k]) || !Usable(series.y[k], log_y)) {
        pen_down = false;
        continue;
      }
      path += (pen_down ? " L" : " M") + Number(px(series.x[k])) + " " +
              Number(py(series.y[k]));
      pen_down = true;
    }
    if (series.line && !path.empty()) {
      *svg << "<path d=\"" << path << "\" fill=\"none\" stroke=\"" << color
           << "\" stroke-width=\"1.8\""
           << (series.dashed ? " stroke-dasharray=\"6 3\"" : "") << "/>\n";
    }
    if (series.markers) {
      for (size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
        if (!std::isfinite(series.x[k]) || !Usable(series.y[k], log_y)) {
          continue;
        }
        DrawMarker(series.marker_shape,
                   px(series.x[k]),
                   py(series.y[k]),
                   series.marker_radius_px,
                   color,
                   svg);
      }
    }
  }
  DrawLabels(panel.labels,
             {left, top, left + plot_width, top + plot_height},
             px,
             py,
             svg);
  *svg << "</g>\n";
}

}  // namespace

std::string DefaultSeriesColor(int index) {
  static const char* const kPalette[] = {"#1f77b4",
                                         "#ff7f0e",
                                         "#2ca02c",
                                         "#d62728",
                                         "#9467bd",
                                         "#8c564b",
                                         "#e377c2",
                                         "#7f7f7f",
                                         "#bcbd22",
                                         "#17becf"};
  return kPalette[((index % 10) + 10) % 10];
}

std::vector<double> AxisTicks(double min,
                              double max,
                              int target_count,
                              bool log_scale) {
  std::vector<double> ticks;
  if (!(min < max) || !std::isfinite(min) || !std::isfinite(max)) return ticks;
  if (log_scale) {
    if (!(min > 0.0)) return ticks;
    const int first = static_cast<int>(std::floor(std::log10(min) + 1e-9));
    const int last = static_cast<int>(std::ceil(std::log10(max) - 1e-9));
    const bool fine = last - first < 2;
    for (int e = first; e <= last; ++e) {
      for (const double m : {1.0, 2.0, 5.0}) {
        if (m != 1.0 && !fine) continue;
        const double value = m * std::pow(10.0, e);
        if (value >= min * (1 - 1e-9) && value <= max * (1 + 1e-9)) {
          ticks.push_back(value);
        }
      }
    }
    return ticks;
  }
  return TicksWithStep(min, max, NiceStep(max - min, target_count));
}

double TextWidthUpperBoundPx(const std::string& text, double font_size_px) {
  // Em fractions above the widest glyph of each class in the three fonts.
  double ems = 0.0;
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if ((byte & 0xC0) == 0x80) continue;  // UTF-8 continuation byte
    // Any other script or symbol, and the widest Latin glyphs: up to an em.
    if (byte >= 0x80 || std::strchr("mwMW@%", c) != nullptr) {
      ems += 1.0;
    } else if (std::isupper(byte)) {
      ems += 0.8;
    } else {
      ems += 0.62;
    }
  }
  return ems * font_size_px;
}

std::string RenderSvg(const PlotFigure& figure) {
  const int num_panels = static_cast<int>(figure.panels.size());
  const int columns = std::max(1, std::min(figure.num_columns, num_panels));
  const int rows = num_panels == 0 ? 0 : (num_panels + columns - 1) / columns;
  // One colour per distinct label, in order of first appearance; the legend
  // draws each label's first series.
  std::vector<std::string> labels, colors;
  std::vector<const PlotSeries*> legend_series;
  std::vector<std::vector<int>> color_index(num_panels);
  for (int p = 0; p < num_panels; ++p) {
    for (const PlotSeries& series : figure.panels[p].series) {
      auto found = std::find(labels.begin(), labels.end(), series.label);
      int index = static_cast<int>(found - labels.begin());
      if (found == labels.end()) {
        labels.push_back(series.label);
        colors.push_back(series.color.empty() ? DefaultSeriesColor(index)
                                              : series.color);
        legend_series.push_back(&series);
      }
      color_index[p].push_back(index);
    }
  }
  const double width = columns * figure.panel_width_px;
  const double title_height = figure.title.empty() ? 0.0 : kFigureTitleHeight;

  // Legend layout: [title] swatch label, swatch label, ... wrapped to the
  // width; continuation rows start under the first entry.
  struct Placement {
    double x = 0.0;
    int row = 0;
  };
  std::vector<Placement> placements;
  int legend_rows = 0;
  if (figure.legend && !labels.empty()) {
    std::vector<double> entry_widths;
    double widest = 0.0;
    for (const std::string& label : labels) {
      entry_widths.push_back(kSwatchWidth + kSwatchGap +
                             TextWidthUpperBoundPx(label, kLegendFontPx));
      widest = std::max(widest, entry_widths.back());
    }
    double first_x = kLegendLeft;
    if (!figure.legend_title.empty()) {
      first_x +=
          TextWidthUpperBoundPx(figure.legend_title, kLegendFontPx) + 10.0;
      // Entries under the title when one would not fit beside it.
      if (first_x + widest > width - 10.0) first_x = kLegendLeft;
    }
    double x = first_x;
    int row = first_x == kLegendLeft && !figure.legend_title.empty() ? 1 : 0;
    for (const double entry_width : entry_widths) {
      if (x > first_x && x + entry_width > width - 10.0) {
        x = first_x;
        ++row;
      }
      placements.push_back({x, row});
      x += entry_width + kEntryGap;
    }
    legend_rows = row + 1;
  }
  const double grid_height = rows * figure.panel_height_px;
  const double height =
      title_height + grid_height + legend_rows * kLegendRowHeight + 10.0;

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << Number(width)
      << "\" height=\"" << Number(height) << "\" viewBox=\"0 0 "
      << Number(width) << " " << Number(height)
      << "\" font-family=\"Helvetica, Arial, sans-serif\">\n";
  svg << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  if (!figure.title.empty()) {
    svg << "<text x=\"" << Number(width / 2)
        << "\" y=\"20\" text-anchor=\"middle\" font-size=\"15\" "
        << "font-weight=\"bold\">" << EscapeMarkup(figure.title) << "</text>\n";
  }
  for (int p = 0; p < num_panels; ++p) {
    const int row = p / columns;  // panels fill the rows left to right
    RenderPanel(figure.panels[p],
                colors,
                color_index[p],
                (p % columns) * figure.panel_width_px,
                title_height + row * figure.panel_height_px,
                figure.panel_width_px,
                figure.panel_height_px,
                &svg);
  }
  if (legend_rows > 0) {
    const double legend_top = title_height + grid_height;
    if (!figure.legend_title.empty()) {
      svg << "<text class=\"legend-title\" x=\"" << Number(kLegendLeft)
          << "\" y=\"" << Number(legend_top + 12.0) << "\" font-size=\""
          << Number(kLegendFontPx) << "\" font-weight=\"bold\">"
          << EscapeMarkup(figure.legend_title) << "</text>\n";
    }
    for (size_t k = 0; k < labels.size(); ++k) {
      const PlotSeries& series = *legend_series[k];
      const double x = placements[k].x;
      const double y = legend_top + placements[k].row * kLegendRowHeight + 12.0;
      svg << "<g class=\"legend-entry\">\n";
      if (series.line) {
        svg << "<line x1=\"" << Number(x) << "\" y1=\"" << Number(y - 4)
            << "\" x2=\"" << Number(x + kSwatchWidth) << "\" y2=\""
            << Number(y - 4) << "\" stroke=\"" << colors[k]
            << "\" stroke-width=\"2\""
            << (series.dashed ? " stroke-dasharray=\"6 3\"" : "") << "/>\n";
      }
      if (series.markers) {
        DrawMarker(series.marker_shape,
                   x + kSwatchWidth / 2,
                   y - 4,
                   std::min(std::max(series.marker_radius_px, 3.0), 5.0),
                   colors[k],
                   &svg);
      }
      svg << "<text class=\"legend-label\" x=\""
          << Number(x + kSwatchWidth + kSwatchGap) << "\" y=\"" << Number(y)
          << "\" font-size=\"" << Number(kLegendFontPx) << "\">"
          << EscapeMarkup(labels[k]) << "</text>\n</g>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace odomcal
