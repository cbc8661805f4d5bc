#include "odomcal/plugin/colmap_report.h"

#include <cmath>
#include <sstream>

#include "odomcal/adapters/timestamp.h"

namespace odomcal {
namespace {

using nlohmann::json;

json Sim3ToJson(const Sim3d& sim3) {
  return {{"scale", sim3.scale},
          {"quaternion_wxyz",
           {sim3.rotation.w(), sim3.rotation.x(), sim3.rotation.y(),
            sim3.rotation.z()}},
          {"translation_m",
           {sim3.translation.x(), sim3.translation.y(), sim3.translation.z()}}};
}

std::string Escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '&': out += "&amp;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

json ColmapCalibrationToJson(const ColmapCalibrationRun& run) {
  json out = CalibrationToJson(run.check.result, run.context);
  json sub_models = json::array();
  for (const ColmapSegment& segment : run.segments) {
    sub_models.push_back({{"path", segment.model_path},
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
         {"segment", stretch.kept_as_segment ? json(stretch.output_segment)
                                             : json(nullptr)}});
  }
  json segment_sources = json::array();
  for (const int input : run.check.input_segment_of_output_segment) {
    segment_sources.push_back(run.segments[input].sub_model);
  }
  json metric_models = json::array();
  for (const MetricSubModel& metric : run.metric_models) {
    metric_models.push_back({{"name", metric.name},
                             {"path", "sparse_metric/" + metric.name},
                             {"segment", metric.output_segment},
                             {"origin_from_sfm", Sim3ToJson(metric.origin_from_sfm)}});
  }
  out["colmap"] = {
      {"sub_models", sub_models},
      {"num_database_images",
       run.num_database_images >= 0 ? json(run.num_database_images) : json(nullptr)},
      {"segment_sub_models", segment_sources},
      {"inconsistent_stretches", stretches},
      {"metric_models", metric_models},
  };
  return out;
}

std::string ColmapReportHtml(const ColmapCalibrationRun& run) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\">"
       << "<title>odomcal calibration report</title></head><body>\n"
       << "<h1>odomcal calibration report</h1>\n<pre>"
       << Escape(CalibrationSummary(run.check.result, run.context))
       << "</pre>\n</body></html>\n";
  return html.str();
}

}  // namespace odomcal
