#include "odomcal/plugin/report/repeatability_report.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <functional>
#include <sstream>

namespace odomcal {

using json = nlohmann::json;

namespace {

json BlockToJson(const RepeatabilityBlock& block) {
  json out = {
      {"first_time_s", FormatTimestampSeconds(block.first_stamp_ns)},
      {"last_time_s", FormatTimestampSeconds(block.last_stamp_ns)},
      {"num_pairs", block.num_pairs},
      {"calibrated", block.calibrated},
      {"reason", block.calibrated ? json(nullptr) : json(block.reason)}};
  if (!block.calibrated) return out;
  const Eigen::Vector3d& rpy = block.roll_pitch_yaw_deg;
  const Eigen::Vector3d& rpy_sigma = block.stddev_roll_pitch_yaw_deg;
  const Eigen::Vector3d& t = block.odom_from_cam.translation;
  out["roll_pitch_yaw_deg"] = {rpy.x(), rpy.y(), rpy.z()};
  out["stddev_roll_pitch_yaw_deg"] = {
      rpy_sigma.x(), rpy_sigma.y(), rpy_sigma.z()};
  out["translation_xy_m"] = {t.x(), t.y()};
  out["stddev_translation_xy_m"] = {block.stddev_translation_xy_m.x(),
                                    block.stddev_translation_xy_m.y()};
  out["metric_scale"] =
      block.metric_scale > 0.0 ? json(block.metric_scale) : json(nullptr);
  out["stddev_metric_scale_rel"] = block.metric_scale > 0.0
                                       ? json(block.stddev_metric_scale_rel)
                                       : json(nullptr);
  return out;
}

std::string TestText(const RepeatabilityTest& test) {
  if (!test.ran) return test.name + " not compared (" + test.reason + ")";
  return test.name + (test.agree ? " agree" : " DISAGREE") + " (chi-square " +
         FormatRounded(test.chi_square) + " on " + std::to_string(test.dof) +
         " dof, p " + PValueText(test.p_value) + ")";
}

double SecondsAfter(int64_t stamp_ns, int64_t start_ns) {
  return ElapsedSeconds(start_ns, stamp_ns);
}

// One panel: each test's blocks at their middle time, as differences from
// the whole drive's value (0, a dashed line), with +-1 sigma marks: the
// blocks' own spread is then readable whatever the value.
PlotPanel ParameterPanel(
    const Repeatability& r,
    const std::string& title,
    const std::string& y_label,
    double whole,
    const std::function<double(const RepeatabilityBlock&)>& value,
    const std::function<double(const RepeatabilityBlock&)>& sigma) {
  PlotPanel panel;
  panel.title = title;
  panel.x_label = "time after the start [s]";
  panel.y_label = y_label;
  const char* colors[] = {"#1f77b4", "#ff7f0e"};
  int index = 0;
  for (const RepeatabilityTest& test : r.tests) {
    const std::string color = colors[index++ % 2];
    PlotSeries values, upper, lower;
    values.label = test.name;
    upper.label = test.name + " + 1 sigma";
    lower.label = test.name + " - 1 sigma";
    values.color = upper.color = lower.color = color;
    for (const RepeatabilityBlock& block : test.blocks) {
      if (!block.calibrated) continue;
      const double t =
          0.5 * (SecondsAfter(block.first_stamp_ns, r.first_stamp_ns) +
                 SecondsAfter(block.last_stamp_ns, r.first_stamp_ns));
      const double difference = value(block) - whole;
      values.x.push_back(t);
      values.y.push_back(difference);
      upper.x.push_back(t);
      upper.y.push_back(difference + sigma(block));
      lower.x.push_back(t);
      lower.y.push_back(difference - sigma(block));
    }
    if (values.x.empty()) continue;
    for (PlotSeries* bound : {&upper, &lower}) {
      bound->line = false;
      bound->marker_shape = MarkerShape::kTriangle;
      bound->marker_radius_px = 2.0;
    }
    panel.series.push_back(values);
    panel.series.push_back(upper);
    panel.series.push_back(lower);
  }
  const double end_s = SecondsAfter(r.last_stamp_ns, r.first_stamp_ns);
  PlotSeries line;
  line.label = "whole drive";
  line.x = {0.0, end_s};
  line.y = {0.0, 0.0};
  line.color = "#444444";
  line.dashed = true;
  line.markers = false;
  panel.series.push_back(line);
  return panel;
}

}  // namespace

PlotFigure RepeatabilityPlot(const Repeatability& r) {
  PlotFigure figure;
  figure.num_columns = 3;
  figure.panel_width_px = 300.0;
  figure.panel_height_px = 220.0;
  const Eigen::Vector3d rpy =
      RollPitchYaw(r.odom_from_cam.rotation) * kRadToDeg;
  const char* names[] = {"roll", "pitch", "yaw"};
  for (int i = 0; i < 3; ++i) {
    figure.panels.push_back(ParameterPanel(
        r,
        names[i],
        std::string(names[i]) + " - whole drive [deg]",
        rpy(i),
        [i](const RepeatabilityBlock& b) { return b.roll_pitch_yaw_deg(i); },
        [i](const RepeatabilityBlock& b) {
          return b.stddev_roll_pitch_yaw_deg(i);
        }));
  }
  for (int i = 0; i < 2; ++i) {
    figure.panels.push_back(ParameterPanel(
        r,
        i == 0 ? "x" : "y",
        i == 0 ? "x - whole drive [mm]" : "y - whole drive [mm]",
        1000.0 * r.odom_from_cam.translation(i),
        [i](const RepeatabilityBlock& b) {
          return 1000.0 * b.odom_from_cam.translation(i);
        },
        [i](const RepeatabilityBlock& b) {
          return 1000.0 * b.stddev_translation_xy_m(i);
        }));
  }
  if (r.metric_scale > 0.0) {
    figure.panels.push_back(ParameterPanel(
        r,
        "metric scale",
        "scale / whole drive - 1 [%]",
        0.0,
        [&r](const RepeatabilityBlock& b) {
          return 100.0 * (b.metric_scale / r.metric_scale - 1.0);
        },
        [&r](const RepeatabilityBlock& b) {
          return 100.0 * b.metric_scale * b.stddev_metric_scale_rel /
                 r.metric_scale;
        }));
  }
  figure.legend_title = "Blocks of the drive:";
  return figure;
}

json RepeatabilityToJson(const std::optional<Repeatability>& repeatability) {
  if (!repeatability) return nullptr;
  const Repeatability& r = *repeatability;
  json tests = json::array();
  for (const RepeatabilityTest& test : r.tests) {
    json blocks = json::array();
    for (const RepeatabilityBlock& block : test.blocks) {
      blocks.push_back(BlockToJson(block));
    }
    tests.push_back(
        {{"name", test.name},
         {"num_blocks", test.num_blocks},
         {"ran", test.ran},
         {"reason", test.ran ? json(nullptr) : json(test.reason)},
         {"chi_square", test.ran ? json(test.chi_square) : json(nullptr)},
         {"dof", test.ran ? json(test.dof) : json(nullptr)},
         {"p_value", test.ran ? json(test.p_value) : json(nullptr)},
         {"alarm_p_value", test.alarm_p_value},
         {"agree", test.ran ? json(test.agree) : json(nullptr)},
         {"blocks", blocks}});
  }
  json change = nullptr;
  if (r.change_stamp_ns) {
    change = {
        {"time_s", FormatTimestampSeconds(*r.change_stamp_ns)},
        {"after_start_s", SecondsAfter(*r.change_stamp_ns, r.first_stamp_ns)},
        {"chi_square", r.change_chi_square},
        {"dof", r.change_dof}};
  }
  return {{"ran", r.ran},
          {"reason", r.ran ? json(nullptr) : json(r.reason)},
          {"consistent", r.ran ? json(r.consistent) : json(nullptr)},
          {"tests", tests},
          {"change", change}};
}

std::string RepeatabilitySummary(const Repeatability& repeatability) {
  if (!repeatability.ran) {
    return "  repeatability: not checked (" + repeatability.reason + ")\n";
  }
  std::string text = "  repeatability:";
  const char* separator = " ";
  for (const RepeatabilityTest& test : repeatability.tests) {
    text += separator + TestText(test);
    separator = "; ";
  }
  if (repeatability.change_stamp_ns) {
    text += "; the mount may have moved " +
            FormatRounded(SecondsAfter(*repeatability.change_stamp_ns,
                                       repeatability.first_stamp_ns)) +
            " s after the start";
  }
  return text + "\n";
}

std::string RepeatabilityHtml(const Repeatability& repeatability) {
  std::ostringstream html;
  html << "<h2>Repeatability</h2>\n";
  if (!repeatability.ran) {
    html << "<p>Not checked: " << EscapeMarkup(repeatability.reason)
         << ".</p>\n";
    return html.str();
  }
  html << "<p>The calibration repeated on time blocks of the drive, with the "
          "final noise model. The blocks agree when the chi-square of their "
          "differences (rotation, x, y and, with one segment, the scale, "
          "weighted by their covariances) is not improbably large. "
       << EscapeMarkup(RepeatabilitySummary(repeatability).substr(2))
       << "</p>\n";
  html << "<table><tr><th>test</th><th>block</th><th>from s</th><th>to "
          "s</th><th>pairs</th><th>roll, pitch, yaw deg (1 sigma)</th>"
          "<th>x, y cm (1 sigma)</th><th>scale (1 sigma %)</th></tr>\n";
  for (const RepeatabilityTest& test : repeatability.tests) {
    for (size_t k = 0; k < test.blocks.size(); ++k) {
      const RepeatabilityBlock& b = test.blocks[k];
      html << "<tr><td>" << EscapeMarkup(test.name) << "</td><td>" << k + 1
           << "</td><td>"
           << FormatRounded(
                  SecondsAfter(b.first_stamp_ns, repeatability.first_stamp_ns))
           << "</td><td>"
           << FormatRounded(
                  SecondsAfter(b.last_stamp_ns, repeatability.first_stamp_ns))
           << "</td><td>" << b.num_pairs << "</td>";
      if (!b.calibrated) {
        html << "<td>not calibrated: " << EscapeMarkup(b.reason)
             << "</td><td>-</td><td>-</td></tr>\n";
        continue;
      }
      html << "<td>";
      for (int i = 0; i < 3; ++i) {
        html << (i ? ", " : "") << FormatPrintf("%.3f", b.roll_pitch_yaw_deg(i))
             << " (" << FormatPrintf("%.3f", b.stddev_roll_pitch_yaw_deg(i))
             << ")";
      }
      html << "</td><td>";
      for (int i = 0; i < 2; ++i) {
        html << (i ? ", " : "")
             << FormatPrintf("%.2f", 100.0 * b.odom_from_cam.translation(i))
             << " ("
             << FormatPrintf("%.2f", 100.0 * b.stddev_translation_xy_m(i))
             << ")";
      }
      html << "</td><td>";
      if (b.metric_scale > 0.0) {
        html << FormatPrintf("%.5f", b.metric_scale) << " ("
             << FormatPrintf("%.2f", 100.0 * b.stddev_metric_scale_rel) << ")";
      } else {
        html << "- (one per segment)";
      }
      html << "</td></tr>\n";
    }
  }
  html << "</table>\n<figure>\n"
       << RenderSvg(RepeatabilityPlot(repeatability))
       << "<figcaption>Each block's estimate minus the whole drive's "
          "estimate (the dashed line at 0), at the middle of the block's time "
          "span (seconds after the first pair), from the halves (blue) and "
          "the quarters (orange) of the drive; the triangles mark one "
          "standard deviation above and below it. Roll, pitch, yaw in degrees "
          "(URDF fixed axes of odom_from_cam), x and y in mm, the metric "
          "scale in % of the whole drive's (one segment only). A mount that "
          "moved shows as blocks before and after a time that differ by more "
          "than their deviations.</figcaption>\n</figure>\n";
  return html.str();
}

}  // namespace odomcal
