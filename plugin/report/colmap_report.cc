#include "odomcal/plugin/report/colmap_report.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/plugin/options/project_flags.h"
#include "odomcal/plugin/report/colmap_calibration_outputs.h"
#include "odomcal/plugin/report/floor_plane_report.h"
#include "odomcal/plugin/report/joint_adjustment_report.h"
#include "odomcal/plugin/report/repeatability_report.h"
#include "odomcal/plugin/report/robot_outputs.h"
#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/angles.h"

#include <cmath>
#include <sstream>
#include <utility>

namespace odomcal {
namespace {

using nlohmann::json;

json Sim3ToJson(const Sim3d& sim3) {
  return {{"scale", sim3.scale},
          {"quaternion_wxyz",
           {sim3.rotation.w(),
            sim3.rotation.x(),
            sim3.rotation.y(),
            sim3.rotation.z()}},
          {"translation_m",
           {sim3.translation.x(), sim3.translation.y(), sim3.translation.z()}}};
}

}  // namespace

ReportContext ProjectReportContext(const ColmapCalibrationInputs& inputs,
                                   const ColmapCalibrationRun& run,
                                   const std::string& command,
                                   nlohmann::json flag_echo) {
  ReportContext context;
  context.command = command;
  for (const ColmapSegment& segment : run.segments) {
    context.camera_paths.push_back(segment.model_path);
  }
  context.odometry_path = inputs.odometry_path;
  context.odometry_format = inputs.odometry_format;
  context.camera_time_unit = inputs.image_timestamps_path.empty()
                                 ? "from image file names"
                                 : TimeUnitName(inputs.image_time_unit);
  // The unit the times were read in (a header suffix overrides the flag).
  context.odometry_time_unit =
      TimeUnitName(run.odometry.time_unit.value_or(inputs.odometry_time_unit));
  context.association_options = inputs.association;
  context.association = run.association;
  context.calibration_options = inputs.calibration;
  context.systematics_options = inputs.systematics;
  context.robot_frames = inputs.robot_frames;
  context.repeatability = run.repeatability;
  context.flag_echo = std::move(flag_echo);
  context.systematics = run.systematics;
  return context;
}

ReportContext ProjectReportContext(const ColmapCalibrationInputs& inputs,
                                   const ColmapCalibrationRun& run,
                                   const std::string& command) {
  return ProjectReportContext(inputs, run, command, ProjectFlagsEcho(inputs));
}

json ColmapCalibrationToJson(const ColmapCalibrationRun& run,
                             const ReportContext& context) {
  json out = CalibrationToJson(run.check.result, context);
  out["joint_adjustment"] = JointAdjustmentToJson(run);
  out["diagnostics"]["two_step"] = TwoStepToJson(run);
  json sub_models = json::array();
  for (const ColmapSegment& segment : run.segments) {
    sub_models.push_back(
        {{"path", segment.model_path},
         {"name", segment.sub_model},
         {"num_registered_images", segment.num_registered_images},
         {"num_images_with_time", segment.trajectory.poses.size()},
         {"num_skipped_without_timestamp",
          segment.num_skipped_without_timestamp}});
  }
  json stretches = json::array();
  for (const InconsistentStretch& stretch : run.check.stretches) {
    stretches.push_back(
        {{"sub_model", run.segments[stretch.input_segment].sub_model},
         {"first_time_s", FormatTimestampSeconds(stretch.first_stamp_ns)},
         {"last_time_s", FormatTimestampSeconds(stretch.last_stamp_ns)},
         {"num_pairs", stretch.num_pairs},
         {"verdict", stretch.kept_as_segment ? "separate_segment" : "rejected"},
         {"segment",
          stretch.kept_as_segment ? json(stretch.output_segment)
                                  : json(nullptr)}});
  }
  json scale_changes = json::array();
  for (const ScaleChangeCut& cut : run.check.scale_changes) {
    scale_changes.push_back(
        {{"sub_model", run.segments[cut.input_segment].sub_model},
         {"time_s", FormatTimestampSeconds(cut.stamp_ns)},
         {"metric_scale_before", cut.scale_before},
         {"metric_scale_after", cut.scale_after},
         {"f_statistic", cut.f_statistic},
         {"f_threshold", cut.f_threshold}});
  }
  json scale_drifts = json::array();
  for (const ScaleDrift& drift : run.check.scale_drifts) {
    json stretches_of_drift = json::array();
    for (const ScaleStretch& stretch : drift.stretches) {
      stretches_of_drift.push_back(
          {{"segment", stretch.output_segment},
           {"first_time_s", FormatTimestampSeconds(stretch.first_stamp_ns)},
           {"last_time_s", FormatTimestampSeconds(stretch.last_stamp_ns)}});
    }
    scale_drifts.push_back(
        {{"sub_model", run.segments[drift.input_segment].sub_model},
         {"first_time_s", FormatTimestampSeconds(drift.first_stamp_ns)},
         {"last_time_s", FormatTimestampSeconds(drift.last_stamp_ns)},
         // null: too few pairs to measure the trend.
         {"relative_drift",
          drift.trend_measured ? json(drift.relative_drift) : json(nullptr)},
         {"relative_drift_stddev",
          drift.trend_measured ? json(drift.relative_drift_stddev)
                               : json(nullptr)},
         {"stretches", stretches_of_drift}});
  }
  json segment_sources = json::array();
  for (const int input : run.check.input_segment_of_output_segment) {
    segment_sources.push_back(run.segments[input].sub_model);
  }
  json metric_models = json::array();
  for (const MetricSubModel& metric : run.metric_models) {
    metric_models.push_back(
        {{"name", metric.name},
         {"path", "sparse_metric/" + metric.name},
         {"segment", metric.output_segment},
         // null for the joint adjustment's model (no single similarity).
         {"origin_from_sfm",
          metric.origin_from_sfm ? Sim3ToJson(*metric.origin_from_sfm)
                                 : json(nullptr)}});
  }
  json duplicates = json::array();
  for (const DuplicateSegment& duplicate : run.duplicate_segments) {
    duplicates.push_back(
        {{"name", duplicate.segment.sub_model},
         {"path", duplicate.segment.model_path},
         {"num_registered_images", duplicate.segment.num_registered_images},
         {"duplicate_of", duplicate.duplicate_of}});
  }
  json mapper_attempts = json::array();
  for (size_t i = 0; i < run.mapper_attempts.size(); ++i) {
    const MapperAttempt& attempt = run.mapper_attempts[i];
    mapper_attempts.push_back(
        {{"matching_round", attempt.matching_round},
         {"chunk", attempt.chunk >= 0 ? json(attempt.chunk) : json(nullptr)},
         {"random_seed", attempt.random_seed},
         {"posed_from_odometry", attempt.posed_from_odometry},
         {"path", attempt.model_path},
         {"produced_model", attempt.produced_model},
         {"num_sub_models", attempt.num_sub_models},
         {"num_registered_images", attempt.num_registered_images},
         {"status",
          attempt.produced_model && attempt.status != CalibrationStatus::kNotRun
              ? json(ToString(attempt.status))
              : json(nullptr)},
         {"initialization",
          attempt.initialization.empty() ? json(nullptr)
                                         : json(attempt.initialization)},
         {"initial_pair",
          attempt.initial_pair.empty() ? json(nullptr)
                                       : json(attempt.initial_pair)},
         {"failure_cause",
          attempt.failure_cause.empty() ? json(nullptr)
                                        : json(attempt.failure_cause)},
         {"num_motion_pairs", attempt.num_pairs},
         {"num_pairs_used", attempt.num_pairs_used},
         {"num_contradicting_pairs", attempt.num_contradicting_pairs},
         {"num_pairs_left_out", attempt.num_pairs_left_out},
         {"chosen", static_cast<int>(i) == run.chosen_mapper_attempt}});
  }
  out["colmap"] = {
      {"sub_models", sub_models},
      {"duplicate_sub_models", duplicates},
      {"num_database_images",
       run.num_database_images >= 0 ? json(run.num_database_images)
                                    : json(nullptr)},
      {"segment_sub_models", segment_sources},
      {"inconsistent_stretches", stretches},
      {"scale_changes", scale_changes},
      {"scale_drifts", scale_drifts},
      {"metric_models", metric_models},
      {"mapper_attempts", mapper_attempts},
  };
  if (!run.colmap_version.empty()) {
    out["colmap"]["version"] = run.colmap_version;
  }
  if (!run.colmap_mapper.empty()) {
    out["colmap"]["mapper"] = run.colmap_mapper;
  }
  if (run.coverage) {
    const ImageCoverage& coverage = *run.coverage;
    json stretches_of_drive = json::array();
    for (const CoverageStretch& stretch : coverage.stretches) {
      stretches_of_drive.push_back(
          {{"in_calibration", stretch.in_calibration},
           {"first_time_s", FormatTimestampSeconds(stretch.first_stamp_ns)},
           {"last_time_s", FormatTimestampSeconds(stretch.last_stamp_ns)},
           {"num_images", stretch.num_images},
           {"num_registered_images", stretch.num_registered},
           {"num_in_calibration", stretch.num_in_calibration},
           {"registered_fraction", stretch.Fraction()}});
    }
    out["colmap"]["registered_fraction"] = coverage.Fraction();
    out["colmap"]["image_coverage"] = {
        {"num_selected_images", coverage.num_selected_images},
        {"num_registered_images", coverage.num_registered_images},
        {"num_in_calibration", coverage.num_in_calibration},
        {"duration_fraction", coverage.duration_fraction},
        {"stretches", stretches_of_drive}};
  }
  return out;
}

std::string ColmapReportHtml(const ColmapCalibrationRun& run,
                             const ReportContext& context) {
  return ColmapReportHtml(run, context, nullptr);
}

std::string ColmapReportHtml(const ColmapCalibrationRun& run,
                             const ReportContext& context,
                             const RigOverrides* rig) {
  const CalibrationResult& result = run.check.result;
  const MotionPairs& input_pairs = run.association.pairs;
  const size_t num_input = input_pairs.size();
  const double nan = std::nan("");

  // Per input pair: used or not, final residuals, consistency measures.
  std::vector<char> used(num_input, 0);
  std::vector<double> rotation_residual(num_input, nan),
      translation_residual(num_input, nan);
  const CalibrationDiagnostics& d = result.diagnostics;
  for (size_t k = 0; k < run.check.input_pair_of_output.size(); ++k) {
    const int input = run.check.input_pair_of_output[k];
    if (k < d.inlier_mask.size()) used[input] = d.inlier_mask[k];
    if (k < d.rotation_residual_deg.size()) {
      rotation_residual[input] = d.rotation_residual_deg[k];
      translation_residual[input] = 1000.0 * d.translation_residual_m[k];
    }
  }
  std::vector<char> in_rejected_stretch(num_input, 0);
  for (const InconsistentStretch& stretch : run.check.stretches) {
    if (stretch.kept_as_segment) continue;
    for (size_t i = 0; i < num_input; ++i) {
      const MotionPair& pair = input_pairs[i];
      if (pair.segment == stretch.input_segment &&
          pair.stamp_i_ns >= stretch.first_stamp_ns &&
          pair.stamp_j_ns <= stretch.last_stamp_ns) {
        in_rejected_stretch[i] = 1;
      }
    }
  }

  // Markers only, one per pair where (mask[i] != 0) == want.
  auto scatter = [&](const std::string& label,
                     const std::vector<double>& values,
                     const std::vector<char>& mask,
                     bool want,
                     const std::string& color,
                     MarkerShape shape) {
    PlotSeries series;
    series.label = label;
    series.color = color;
    series.line = false;
    series.marker_shape = shape;
    for (size_t i = 0; i < values.size(); ++i) {
      if ((mask[i] != 0) != want) continue;
      series.x.push_back(static_cast<double>(i));
      series.y.push_back(values[i]);
    }
    return series;
  };

  PlotFigure top;
  top.title = "Top view in the odometry frame";
  top.num_columns = 1;
  top.panel_width_px = 760;
  top.panel_height_px = 560;
  top.legend_title = "Trajectories:";
  {
    PlotPanel& panel = top.panels.emplace_back();
    panel.x_label = "x [m]";
    panel.y_label = "y [m]";
    panel.equal_aspect = true;
    PlotSeries odometry{
        "odometry (robot base)", {}, {}, "#1f77b4", false, false};
    for (const StampedPose& pose : run.odometry.poses) {
      odometry.x.push_back(pose.world_from_sensor.translation.x());
      odometry.y.push_back(pose.world_from_sensor.translation.y());
    }
    panel.series.push_back(odometry);
    // Colours unlike the pair plots' blue/orange and green/red.
    static const char* const kCameraColors[] = {
        "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"};
    for (size_t m = 0; m < run.metric_models.size(); ++m) {
      const MetricSubModel& metric = run.metric_models[m];
      PlotSeries cameras;
      cameras.label = "camera centres, sub-model " + metric.name;
      cameras.color = kCameraColors[m % 6];
      cameras.line = false;
      cameras.marker_radius_px = 1.8;
      for (const auto& [id, image] : metric.model.images) {
        const Eigen::Vector3d position =
            Inverse(image.cam_from_world).translation;
        cameras.x.push_back(position.x());
        cameras.y.push_back(position.y());
      }
      panel.series.push_back(cameras);
    }
    if (!run.odometry.poses.empty()) {
      const Eigen::Vector3d& first =
          run.odometry.poses.front().world_from_sensor.translation;
      const Eigen::Vector3d& last =
          run.odometry.poses.back().world_from_sensor.translation;
      PlotSeries start{
          "start", {first.x()}, {first.y()}, "#000000", false, true};
      start.line = false;
      start.marker_shape = MarkerShape::kSquare;
      start.marker_radius_px = 5.0;
      PlotSeries end{"end", {last.x()}, {last.y()}, "#000000", false, true};
      end.line = false;
      end.marker_shape = MarkerShape::kTriangle;
      end.marker_radius_px = 5.5;
      panel.series.push_back(start);
      panel.series.push_back(end);
    }
  }

  std::vector<double> yaw(num_input), mismatch(num_input),
      ratio(num_input, nan);
  for (size_t i = 0; i < num_input; ++i) {
    const MotionPair& pair = input_pairs[i];
    yaw[i] = LogRotation(pair.odom_i_from_odom_j.rotation).z() * kRadToDeg;
    mismatch[i] = std::abs(RotationAngle(pair.odom_i_from_odom_j.rotation) -
                           RotationAngle(pair.cam_i_from_cam_j.rotation)) *
                  kRadToDeg;
  }
  // Step-length ratio: the camera displacement the odometry and the
  // extrinsic predict, |R_A p + t_A - p|, over the one COLMAP measured,
  // s |t_B| (s of the pair's final segment); 1 when both agree, also for
  // turns in place.
  for (size_t k = 0; k < run.check.input_pair_of_output.size(); ++k) {
    const int input = run.check.input_pair_of_output[k];
    const int segment =
        k < run.check.pairs.size() ? run.check.pairs[k].segment : -1;
    if (!result.has_estimate || segment < 0 ||
        segment >= static_cast<int>(result.metric_scales.size())) {
      continue;
    }
    const Rigid3d& a = input_pairs[input].odom_i_from_odom_j;
    const Eigen::Vector3d& p = result.odom_from_cam.translation;
    const double predicted = (a.rotation * p + a.translation - p).norm();
    const double measured =
        result.metric_scales[segment] *
        input_pairs[input].cam_i_from_cam_j.translation.norm();
    if (measured > 0.0 && std::isfinite(measured))
      ratio[input] = predicted / measured;
  }

  // Two meanings, two figures with their own legends and colours: whether
  // the calibration used a pair (blue / orange), and whether the odometry
  // contradicts COLMAP there (green / red).
  PlotFigure fit;
  fit.title = "Calibration fit per motion pair";
  fit.num_columns = 3;
  fit.panel_width_px = 320;
  fit.panel_height_px = 270;
  fit.legend_title = "Pair in the calibration:";
  auto add_fit_panel = [&](const std::string& title,
                           const std::string& y_label,
                           const std::vector<double>& values) {
    PlotPanel& panel = fit.panels.emplace_back();
    panel.title = title;
    panel.x_label = "motion pair (time order)";
    panel.y_label = y_label;
    panel.series.push_back(
        scatter("used", values, used, true, "#1f77b4", MarkerShape::kCircle));
    panel.series.push_back(scatter("not used (outlier or left out)",
                                   values,
                                   used,
                                   false,
                                   "#ff7f0e",
                                   MarkerShape::kDiamond));
  };
  add_fit_panel("rotation residual", "deg", rotation_residual);
  add_fit_panel("translation residual", "mm", translation_residual);
  add_fit_panel("odometry yaw change", "deg", yaw);

  PlotFigure consistency;
  consistency.title = "COLMAP vs odometry per motion pair";
  consistency.num_columns = 2;
  consistency.legend_title = "Pair according to the odometry:";
  std::vector<char> consistent(num_input);
  for (size_t i = 0; i < num_input; ++i)
    consistent[i] = !in_rejected_stretch[i];
  auto add_consistency_panel = [&](const std::string& title,
                                   const std::string& y_label,
                                   const std::vector<double>& values) {
    PlotPanel& panel = consistency.panels.emplace_back();
    panel.title = title;
    panel.x_label = "motion pair (time order)";
    panel.y_label = y_label;
    panel.series.push_back(scatter("consistent",
                                   values,
                                   consistent,
                                   true,
                                   "#2ca02c",
                                   MarkerShape::kCircle));
    panel.series.push_back(scatter("in a stretch rejected as contradicting",
                                   values,
                                   consistent,
                                   false,
                                   "#d62728",
                                   MarkerShape::kSquare));
  };
  add_consistency_panel(
      "rotation angle difference", "| |θ_cam| − |θ_odom| | [deg]", mismatch);
  add_consistency_panel("step length ratio", "predicted / measured", ratio);

  // Every figure: the SVG and a caption naming each quantity and symbol.
  auto figure_html = [](const PlotFigure& figure, const std::string& caption) {
    return "<figure>\n" + RenderSvg(figure) + "<figcaption>" + caption +
           "</figcaption>\n</figure>\n";
  };
  const std::string pair_definition =
      "A <em>motion pair</em> is the motion between two consecutive keyframes, "
      "measured "
      "twice: by the odometry (A) and by COLMAP (B). The x axis counts the "
      "pairs in "
      "time order. ";

  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       << "<title>odomcal calibration report</title><style>"
       << "body{font-family:sans-serif;max-width:1000px;margin:2em "
          "auto;padding:0 1em;"
          "color:#222}"
       << "pre{background:#f6f6f6;padding:1em;white-space:pre-wrap;"
          "overflow-wrap:anywhere}"
       << "li,p,td,figcaption{overflow-wrap:anywhere}"
       << "svg{max-width:100%;height:auto}"
       << "figure{margin:1em "
          "0}figcaption{font-size:0.9em;color:#444;max-width:60em}"
       << "table{border-collapse:collapse}th,td{border:1px solid "
          "#ccc;padding:0.2em 0.6em}"
       << ".status{font-size:1.3em;font-weight:bold}"
       << ".success{color:#2a7a2a}.failure{color:#b02020}"
       << "li.warning{color:#a05a00}</style></head><body>\n"
       << "<h1>odomcal calibration report</h1>\n"
       << "<p class=\"status " << (result.IsSuccess() ? "success" : "failure")
       << "\">" << EscapeMarkup(ToString(result.status)) << ": "
       << EscapeMarkup(result.message) << "</p>\n"
       << "<h2>Estimate (3-sigma bounds)</h2>\n<pre>"
       << EscapeMarkup(CalibrationSummary(result, context)) << "</pre>\n"
       << "<p>odom_from_cam maps camera coordinates to odometry (robot base) "
          "coordinates; "
          "roll, pitch, yaw in degrees; x, y, z in cm; the bounds are three "
          "standard "
          "deviations of the refinement's covariance; the metric scale is "
          "metres per "
          "COLMAP unit, one per segment (a sub-model, or a part of one with "
          "its own "
          "scale).</p>\n";
  html << "<h2>Warnings</h2>\n<ul>";
  if (result.warnings.empty()) html << "<li>none</li>";
  for (const std::string& warning : result.warnings) {
    html << "<li class=\"warning\">" << EscapeMarkup(warning) << "</li>";
  }
  html << "</ul>\n";
  if (rig != nullptr) html << rig->report_section;
  html << RobotUseItHtml(rig != nullptr ? rig->robot
                                        : RobotDescriptionOf(result, context));
  html << "<h2>Trajectories</h2>\n"
       << figure_html(top,
                      "Seen from above, x and y in metres at the same scale. "
                      "Blue line: the "
                      "odometry's position of the robot base over time. Dots: "
                      "the centre of each "
                      "registered image's camera, from COLMAP after the "
                      "calibration (metric scale "
                      "and alignment into the odometry frame), one colour per "
                      "exported sub-model. "
                      "The dots run beside the line by the camera's mounting "
                      "offset. Black "
                      "square: the first odometry pose (start); black "
                      "triangle: the last (end).")
       << JointAdjustmentHtml(run) << FloorPlaneHtml(run)
       << "\n<h2>Motion pairs</h2>\n"
       << figure_html(fit,
                      pair_definition +
                          "<em>Rotation residual</em>: the angle (deg) of the "
                          "rotation left "
                          "between A and B after the calibration; "
                          "<em>translation residual</em>: "
                          "the length (mm) of the translation left. Both are "
                          "shown only for pairs "
                          "the calibration saw. <em>Odometry yaw change</em>: "
                          "the yaw angle (deg) "
                          "the robot turned over the pair; pairs that turn "
                          "determine the rotation "
                          "and x/y of the extrinsic. Blue: used in the "
                          "calibration; orange: not "
                          "used (outside RANSAC's gate or beyond the noise "
                          "estimated from the data, or left out with a "
                          "contradicting stretch).")
       << figure_html(
              consistency,
              pair_definition +
                  "<em>Rotation angle difference</em> | |&theta;_cam| &minus; "
                  "|&theta;_odom| | (deg): &theta;_cam is the angle the camera "
                  "rotated "
                  "over the pair according to COLMAP, &theta;_odom the angle "
                  "the robot "
                  "rotated according to the odometry. A rigid mount rotates "
                  "both by the "
                  "same angle, so this needs no calibration and should be near "
                  "0. "
                  "<em>Step length ratio</em>: the camera's displacement "
                  "predicted from "
                  "the odometry and the calibrated extrinsic, divided by the "
                  "displacement "
                  "COLMAP measured times the segment's metric scale; 1 when "
                  "they agree. "
                  "Green: consistent; red: in a stretch where COLMAP "
                  "contradicts the "
                  "odometry (e.g. a folded reconstruction), left out of the "
                  "calibration.");
  if (context.repeatability) html << RepeatabilityHtml(*context.repeatability);
  html << "<h2>COLMAP sub-models</h2>\n";
  if (!run.colmap_version.empty()) {
    html << "<p>Reconstructed by COLMAP " << EscapeMarkup(run.colmap_version);
    if (!run.colmap_mapper.empty()) {
      html << " (" << EscapeMarkup(run.colmap_mapper) << ")";
    }
    html << ".</p>\n";
  }
  html << "<ul>";
  for (const ColmapSegment& segment : run.segments) {
    html << "<li>" << EscapeMarkup(segment.model_path) << ": "
         << segment.num_registered_images << " registered images</li>";
  }
  html << "</ul>\n";
  if (run.coverage) {
    const ImageCoverage& coverage = *run.coverage;
    html << "<p>" << EscapeMarkup(CoverageClause(coverage)) << ", covering "
         << static_cast<int>(std::lround(100.0 * coverage.duration_fraction))
         << " % of the drive's duration";
    int num_gaps = 0;
    for (const CoverageStretch& stretch : coverage.stretches) {
      num_gaps += stretch.in_calibration ? 0 : 1;
    }
    html << "; " << num_gaps << (num_gaps == 1 ? " gap" : " gaps")
         << " of 3 or more images not in it.</p>\n";
  }
  if (!run.mapper_attempts.empty()) {
    html
        << "<h2>COLMAP mapper runs</h2>\n<p>The mapper runs again with another "
           "random seed while motion pairs of its model contradict the "
           "odometry; "
           "the model contradicted least is calibrated. When the seeds do not "
           "help, "
           "the images are matched again (matching round 1) and mapped again. "
           "A drive mapped in chunks maps again only a chunk with a stretch "
           "left out as folded (chunk: WS/chunks/chunk_&lt;k&gt;_images.txt; "
           "the other chunks as chosen before), after first posing the "
           "fold from the odometry and letting COLMAP triangulate and adjust "
           "it again (&quot;folds posed from the odometry&quot;). A run "
           "that gives no model is followed by other ways to start the "
           "model: initial pairs chosen from the odometry and the verified "
           "matches, COLMAP's initialisation tests relaxed, and for a chunk "
           "its neighbours' images (docs/cli.md)."
           "</p>\n<table>"
           "<tr><th>matching "
           "round</th><th>chunk</th><th>--random_seed</th><th>start</th>"
           "<th>sub-models</th>"
           "<th>registered images</th><th>calibration status</th><th>pairs "
           "used</th>"
           "<th>contradicting pairs</th><th>calibrated in this "
           "report</th></tr>";
    for (size_t i = 0; i < run.mapper_attempts.size(); ++i) {
      const MapperAttempt& attempt = run.mapper_attempts[i];
      html << "<tr><td>" << attempt.matching_round << "</td><td>"
           << (attempt.chunk >= 0 ? "chunk_" + std::to_string(attempt.chunk)
                                  : std::string("-"))
           << "</td><td>" << attempt.random_seed
           << (attempt.posed_from_odometry ? ", folds posed from the odometry"
                                           : "")
           << "</td><td>"
           << (attempt.initialization.empty()
                   ? std::string("-")
                   : EscapeMarkup(attempt.initialization))
           << (attempt.initial_pair.size() == 2
                   ? " " + EscapeMarkup(attempt.initial_pair[0]) + " + " +
                         EscapeMarkup(attempt.initial_pair[1])
                   : std::string())
           << "</td><td>" << attempt.num_sub_models << "</td><td>"
           << attempt.num_registered_images << "</td><td>"
           << (!attempt.produced_model
                   ? "no model" +
                         (attempt.failure_cause.empty()
                              ? std::string()
                              : ": " + EscapeMarkup(attempt.failure_cause))
               : attempt.status == CalibrationStatus::kNotRun
                   ? std::string("not calibrated alone")
                   : EscapeMarkup(ToString(attempt.status)))
           << "</td><td>" << attempt.num_pairs_used << " of "
           << attempt.num_pairs << "</td><td>"
           << attempt.num_contradicting_pairs << "</td><td>"
           << (static_cast<int>(i) == run.chosen_mapper_attempt ? "yes" : "no")
           << "</td></tr>";
    }
    html << "</table>\n";
  }
  html << "<p>Conventions: x_in_odom = odom_from_cam * x_in_cam; Hamilton "
          "quaternions, order w, x, y, z; metres; metric scale in metres per "
          "reconstruction unit. The same numbers, and the per-pair values "
          "plotted "
          "here, are in calibration.json "
          "(docs/result_schema.md).</p>\n</body></html>\n";
  return html.str();
}

}  // namespace odomcal
