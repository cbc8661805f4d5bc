// Layout: panels on a grid of num_columns, each with a fixed margin for its
// title, tick labels and axis labels; the legend is a row of entries under
// the grid, wrapped to the figure width. Axis ranges come from the finite
// data (log-y: positive data), widened to the outer ticks; an empty or
// constant range gets a unit (or one-decade) span. Text is XML-escaped.

#include "odomcal/plugin/svg_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace odomcal {
namespace {

constexpr double kMarginLeft = 62.0;
constexpr double kMarginRight = 14.0;
constexpr double kMarginTop = 28.0;
constexpr double kMarginBottom = 44.0;
constexpr double kFigureTitleHeight = 30.0;
constexpr double kLegendRowHeight = 20.0;
constexpr double kLegendEntryWidth = 120.0;
constexpr int kTargetTicks = 6;

std::string Escape(const std::string& text) {
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

void RenderPanel(const PlotPanel& panel,
                 const std::vector<std::string>& colors,
                 const std::vector<int>& color_index,
                 double x0,
                 double y0,
                 double width,
                 double height,
                 std::ostringstream* svg) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo;
  double y_lo = x_lo, y_hi = -x_lo;
  for (const PlotSeries& series : panel.series) {
    for (size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
      if (!std::isfinite(series.x[k]) || !Usable(series.y[k], panel.log_y)) {
        continue;
      }
      x_lo = std::min(x_lo, series.x[k]);
      x_hi = std::max(x_hi, series.x[k]);
      y_lo = std::min(y_lo, series.y[k]);
      y_hi = std::max(y_hi, series.y[k]);
    }
  }
  if (!panel.log_y && y_lo > 0.0) y_lo = 0.0;  // RMSE-like data: from zero
  const Axis x_axis = MakeAxis(x_lo, x_hi, false);
  const Axis y_axis = MakeAxis(y_lo, y_hi, panel.log_y);
  const double left = x0 + kMarginLeft;
  const double top = y0 + kMarginTop;
  const double plot_width = width - kMarginLeft - kMarginRight;
  const double plot_height = height - kMarginTop - kMarginBottom;
  auto px = [&](double x) { return left + x_axis.Fraction(x) * plot_width; };
  auto py = [&](double y) {
    return top + (1.0 - y_axis.Fraction(y)) * plot_height;
  };

  *svg << "<g>\n";
  *svg << "<text x=\"" << Number(left + plot_width / 2) << "\" y=\""
       << Number(y0 + 18) << "\" text-anchor=\"middle\" font-size=\"13\" "
       << "font-weight=\"bold\">" << Escape(panel.title) << "</text>\n";
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
         << "\" text-anchor=\"middle\" font-size=\"11\">" << TickLabel(tick)
         << "</text>\n";
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
         << "\" text-anchor=\"end\" font-size=\"11\">" << TickLabel(tick)
         << "</text>\n";
  }
  *svg << "<text x=\"" << Number(left + plot_width / 2) << "\" y=\""
       << Number(y0 + height - 8) << "\" text-anchor=\"middle\" "
       << "font-size=\"12\">" << Escape(panel.x_label) << "</text>\n";
  const double label_x = x0 + 14;
  const double label_y = top + plot_height / 2;
  *svg << "<text x=\"" << Number(label_x) << "\" y=\"" << Number(label_y)
       << "\" text-anchor=\"middle\" font-size=\"12\" transform=\"rotate(-90 "
       << Number(label_x) << " " << Number(label_y) << ")\">"
       << Escape(panel.y_label + (panel.log_y ? " (log)" : "")) << "</text>\n";

  for (size_t s = 0; s < panel.series.size(); ++s) {
    const PlotSeries& series = panel.series[s];
    const std::string& color = colors[color_index[s]];
    std::string path;
    bool pen_down = false;
    for (size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
      if (!std::isfinite(series.x[k]) || !Usable(series.y[k], panel.log_y)) {
        pen_down = false;
        continue;
      }
      path += (pen_down ? " L" : " M") + Number(px(series.x[k])) + " " +
              Number(py(series.y[k]));
      pen_down = true;
    }
    if (!path.empty()) {
      *svg << "<path d=\"" << path << "\" fill=\"none\" stroke=\"" << color
           << "\" stroke-width=\"1.8\""
           << (series.dashed ? " stroke-dasharray=\"6 3\"" : "") << "/>\n";
    }
    if (series.markers) {
      for (size_t k = 0; k < series.x.size() && k < series.y.size(); ++k) {
        if (!std::isfinite(series.x[k]) || !Usable(series.y[k], panel.log_y)) {
          continue;
        }
        *svg << "<circle cx=\"" << Number(px(series.x[k])) << "\" cy=\""
             << Number(py(series.y[k])) << "\" r=\"2.5\" fill=\"" << color
             << "\"/>\n";
      }
    }
  }
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
  const double step = NiceStep(max - min, target_count);
  const double start = std::ceil(min / step - 1e-9) * step;
  for (double value = start; value <= max + 1e-9 * step; value += step) {
    ticks.push_back(std::abs(value) < 1e-12 * step ? 0.0 : value);
  }
  return ticks;
}

std::string RenderSvg(const PlotFigure& figure) {
  const int num_panels = static_cast<int>(figure.panels.size());
  const int columns = std::max(1, std::min(figure.num_columns, num_panels));
  const int rows = num_panels == 0 ? 0 : (num_panels + columns - 1) / columns;
  // One colour per distinct label, in order of first appearance.
  std::vector<std::string> labels, colors;
  std::vector<bool> label_dashed;
  std::vector<std::vector<int>> color_index(num_panels);
  for (int p = 0; p < num_panels; ++p) {
    for (const PlotSeries& series : figure.panels[p].series) {
      auto found = std::find(labels.begin(), labels.end(), series.label);
      int index = static_cast<int>(found - labels.begin());
      if (found == labels.end()) {
        labels.push_back(series.label);
        colors.push_back(series.color.empty() ? DefaultSeriesColor(index)
                                              : series.color);
        label_dashed.push_back(series.dashed);
      }
      color_index[p].push_back(index);
    }
  }
  const double width = columns * figure.panel_width_px;
  const double title_height = figure.title.empty() ? 0.0 : kFigureTitleHeight;
  const int per_row = std::max(1, static_cast<int>(width / kLegendEntryWidth));
  const int legend_rows =
      figure.legend && !labels.empty()
          ? (static_cast<int>(labels.size()) + per_row - 1) / per_row
          : 0;
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
        << "font-weight=\"bold\">" << Escape(figure.title) << "</text>\n";
  }
  for (int p = 0; p < num_panels; ++p) {
    RenderPanel(figure.panels[p],
                colors,
                color_index[p],
                (p % columns) * figure.panel_width_px,
                title_height + (p / columns) * figure.panel_height_px,
                figure.panel_width_px,
                figure.panel_height_px,
                &svg);
  }
  if (legend_rows > 0) {
    const double legend_top = title_height + grid_height;
    for (size_t k = 0; k < labels.size(); ++k) {
      const double x = 20.0 + (k % per_row) * kLegendEntryWidth;
      const double y = legend_top + (k / per_row) * kLegendRowHeight + 12.0;
      svg << "<line x1=\"" << Number(x) << "\" y1=\"" << Number(y - 4)
          << "\" x2=\"" << Number(x + 26) << "\" y2=\"" << Number(y - 4)
          << "\" stroke=\"" << colors[k] << "\" stroke-width=\"2\""
          << (label_dashed[k] ? " stroke-dasharray=\"6 3\"" : "") << "/>\n";
      svg << "<text x=\"" << Number(x + 32) << "\" y=\"" << Number(y)
          << "\" font-size=\"12\">" << Escape(labels[k]) << "</text>\n";
    }
  }
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace odomcal
