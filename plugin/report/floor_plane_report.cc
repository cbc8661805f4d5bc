#include "odomcal/plugin/report/floor_plane_report.h"

#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace odomcal {

using nlohmann::json;

namespace {

// A plane was fitted (its parameters hold), whether or not z came from it.
bool HasPlane(const FloorPlane& floor) {
  return floor.status == FloorPlaneStatus::kFitted ||
         floor.status == FloorPlaneStatus::kSloped ||
         floor.status == FloorPlaneStatus::kDisagreesWithMotion ||
         floor.status == FloorPlaneStatus::kTiltUncertain;
}

}  // namespace

json FloorPlaneToJson(const CalibrationResult& result) {
  if (!result.floor_plane) return nullptr;
  const FloorPlane& f = *result.floor_plane;
  json out = {
      {"status", ToString(f.status)},
      {"used_for_translation_z",
       result.observability.translation_z_source ==
           TranslationZSource::kFloorPlane},
      {"translation_z_held_reason",
       result.floor_z_held_reason.empty() ? json(nullptr)
                                          : json(result.floor_z_held_reason)},
      {"num_candidates", f.num_candidates},
      {"num_inliers", f.num_inliers},
      {"num_beside", f.num_beside},
  };
  if (!HasPlane(f)) return out;
  out["inlier_rms_m"] = f.inlier_rms_m;
  out["normal_in_odom_origin"] = {f.normal.x(), f.normal.y(), f.normal.z()};
  out["offset_m"] = f.offset_m;
  out["tilt_deg"] = f.tilt_deg;
  out["tilt_chi_square"] = f.tilt_chi_square;
  out["camera_height_m"] = f.camera_height_m;
  out["camera_height_stddev_m"] = f.camera_height_stddev_m;
  out["camera_height_spread_m"] = f.camera_height_spread_m;
  out["camera_height_model_difference_m"] =
      std::isfinite(f.camera_height_model_difference_m)
          ? json(f.camera_height_model_difference_m)
          : json(nullptr);
  out["camera_height_pixel_aspect_m"] = f.camera_height_pixel_aspect_m;
  out["pixel_aspect_change"] = f.pixel_aspect_change;
  out["odometry_height_m"] = f.odometry_height_m;
  out["floor_roll_deg"] = f.floor_roll_deg;
  out["floor_pitch_deg"] = f.floor_pitch_deg;
  out["roll_pitch_correction_deg"] = {
      f.roll_pitch_correction_rad.x() * kRadToDeg,
      f.roll_pitch_correction_rad.y() * kRadToDeg};
  out["roll_pitch_correction_stddev_deg"] = {
      std::sqrt(f.roll_pitch_correction_covariance(0, 0)) * kRadToDeg,
      std::sqrt(f.roll_pitch_correction_covariance(1, 1)) * kRadToDeg};
  out["tilt_parts"] = f.tilt_parts;
  out["tilt_parts_sigma_deg"] = f.tilt_parts_sigma_rad * kRadToDeg;
  out["tilt_band_sigma_deg"] = f.tilt_band_sigma_rad * kRadToDeg;
  out["disagreement_chi_square"] = f.disagreement_chi_square;
  out["chi_square_threshold"] = f.disagreement_threshold;
  return out;
}

std::string FloorPlaneSummary(const CalibrationResult& result) {
  if (!result.floor_plane) return "";
  const FloorPlane& f = *result.floor_plane;
  std::ostringstream out;
  if (!HasPlane(f)) {
    out << "  floor plane: none (" << f.reason << ")\n";
    return out.str();
  }
  out << "  floor plane: " << f.num_inliers << " of " << f.num_candidates
      << " points, rms " << FormatPrintf("%.1f mm", 1000.0 * f.inlier_rms_m)
      << ", tilted " << FormatPrintf("%.2f deg", f.tilt_deg) << "; camera "
      << FormatPrintf("%.2f cm", 100.0 * f.camera_height_m) << " above it";
  if (std::isfinite(f.camera_height_model_difference_m)) {
    out << " ("
        << FormatPrintf("%+.1f mm", 1000.0 * f.camera_height_model_difference_m)
        << " on the joint adjustment's model; the height's sigma, "
        << FormatPrintf("%.1f mm", 1000.0 * f.camera_height_stddev_m)
        << ", includes the difference)";
  }
  if (f.camera_height_pixel_aspect_m > 0.0) {
    out << " (fx / fy " << FormatPrintf("%.4f", f.pixel_aspect_change)
        << " times its value before the bundle adjustment: the height's "
           "sigma includes "
        << FormatPrintf("%.1f mm", 1000.0 * f.camera_height_pixel_aspect_m)
        << " for it)";
  }
  out << "\n";
  out << "  floor roll/pitch " << FormatPrintf("%.3f", f.floor_roll_deg)
      << " / " << FormatPrintf("%.3f deg", f.floor_pitch_deg)
      << " (motion's corrected by "
      << FormatPrintf("%.3f deg",
                      f.roll_pitch_correction_rad.norm() * kRadToDeg)
      << ", chi-square " << FormatPrintf("%.2f", f.disagreement_chi_square)
      << (f.disagreement_chi_square <= f.disagreement_threshold ? " <= "
                                                                : " > ")
      << FormatPrintf("%.2f", f.disagreement_threshold) << "; the floor's "
      << FormatPrintf(
             "+- %.3f deg",
             std::sqrt(std::max(f.roll_pitch_correction_covariance(0, 0),
                                f.roll_pitch_correction_covariance(1, 1))) *
                 kRadToDeg)
      << " own sigma, "
      << FormatPrintf("%.3f deg", f.tilt_band_sigma_rad * kRadToDeg)
      << " of it from its near and far points)\n";
  return out.str();
}

std::string TranslationZOrigin(const CalibrationResult& result) {
  const Observability& o = result.observability;
  if (o.translation_z == Determination::kEstimated) {
    if (o.translation_z_source == TranslationZSource::kFloorPlane &&
        result.floor_plane) {
      return "estimated from the floor plane (camera height " +
             FormatPrintf("%.2f cm",
                          100.0 * result.floor_plane->camera_height_m) +
             " minus --odometry_height_m)";
    }
    return "estimated (SE(3) odometry, rotation axes not all parallel)";
  }
  const TranslationZPrior& prior = result.translation_z_prior;
  std::string text;
  if (prior.used && prior.moved_by_data) {
    text = "under its prior " + FormatPrintf("%.2f cm", 100.0 * prior.held_m) +
           " +- " + FormatPrintf("%.2f cm", 300.0 * prior.prior_stddev_m) +
           " (3 sigma; --fixed_translation_z_m, --translation_z_prior_sigma_m)"
           ", moved by the SE(3) odometry, which alone gives +- " +
           FormatPrintf("%.2f cm", 300.0 * prior.data_stddev_m) +
           "; x, y and the rotation include its uncertainty";
  } else if (prior.used) {
    text =
        "fixed (unobservable under planar motion; --fixed_translation_z_m; "
        "prior +- " +
        FormatPrintf("%.2f cm", 300.0 * prior.prior_stddev_m) +
        " (3 sigma) not moved by the data)";
  } else {
    text = "fixed (unobservable under planar motion; --fixed_translation_z_m)";
  }
  if (!result.floor_z_held_reason.empty()) {
    text += "; not from the floor: " + result.floor_z_held_reason;
  }
  return text;
}

std::string FloorPlaneHtml(const ColmapCalibrationRun& run) {
  const CalibrationResult& result = run.check.result;
  if (!result.floor_plane || !HasPlane(*result.floor_plane)) {
    return "";
  }
  const FloorPlane& f = *result.floor_plane;
  // Side view along the path's longest horizontal extent: the plane's
  // points (within 2 cm), the cameras, the floor line and the odometry
  // frame's height.
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
  std::vector<Eigen::Vector3d> centres;
  for (const MetricSubModel& metric : run.metric_models) {
    for (const auto& [id, image] : metric.model.images) {
      const Eigen::Vector3d c = Inverse(image.cam_from_world).translation;
      centres.push_back(c);
      min_x = std::min(min_x, c.x());
      max_x = std::max(max_x, c.x());
      min_y = std::min(min_y, c.y());
      max_y = std::max(max_y, c.y());
    }
  }
  const int axis = (max_x - min_x) >= (max_y - min_y) ? 0 : 1;
  const char* axis_name = axis == 0 ? "x" : "y";
  PlotFigure figure;
  figure.num_columns = 1;
  figure.panel_width_px = 900.0;
  figure.panel_height_px = 260.0;
  PlotPanel& panel = figure.panels.emplace_back();
  panel.title = "side view of the metric model";
  panel.x_label = std::string(axis_name) + " in the odometry frame [m]";
  panel.y_label = "z [m]";
  PlotSeries points{"floor points", {}, {}, "#8c8c8c", false, true, false};
  points.marker_radius_px = 1.0;
  // The cameras sit at z, the camera height above the floor (the model
  // moved with z when it was set from the floor).
  const double floor_z =
      result.odom_from_cam.translation.z() - f.camera_height_m;
  const double distance = 0.02;
  size_t count = 0;
  for (const MetricSubModel& metric : run.metric_models) {
    for (const auto& [id, point] : metric.model.points3D) {
      if (std::abs(point.xyz.z() - floor_z) > distance) continue;
      if (++count % 4 != 0) continue;  // a sample keeps the SVG small
      points.x.push_back(point.xyz(axis));
      points.y.push_back(point.xyz.z());
    }
  }
  PlotSeries cameras{"camera centres", {}, {}, "#1f77b4", false, true, false};
  for (const Eigen::Vector3d& c : centres) {
    cameras.x.push_back(c(axis));
    cameras.y.push_back(c.z());
  }
  const double lo = axis == 0 ? min_x : min_y;
  const double hi = axis == 0 ? max_x : max_y;
  PlotSeries floor_line{"fitted floor",
                        {lo, hi},
                        {floor_z, floor_z},
                        "#d62728",
                        false,
                        false,
                        true};
  PlotSeries odom_line{
      "odometry frame origin height",
      {lo, hi},
      {floor_z + f.odometry_height_m, floor_z + f.odometry_height_m},
      "#2ca02c",
      true,
      false,
      true};
  panel.series = {points, floor_line, odom_line, cameras};
  std::ostringstream html;
  html << "<h2>Floor plane</h2>\n<figure>\n"
       << RenderSvg(figure)
       << "<figcaption>The metric model seen from the side (" << axis_name
       << " against z, metres). Grey: model points within 2 cm of the fitted "
          "floor (every fourth). Red: the floor plane fitted to the points "
          "below the cameras near the path (RANSAC, then a weighted "
          "least-squares refit). Blue: the camera centres, "
       << EscapeMarkup(FormatPrintf("%.2f cm", 100.0 * f.camera_height_m))
       << " above the floor on average"
       << (std::isfinite(f.camera_height_model_difference_m)
               ? EscapeMarkup(
                     " (" +
                     FormatPrintf("%+.1f mm",
                                  1000.0 * f.camera_height_model_difference_m) +
                     " on the joint adjustment's model, a difference the "
                     "height's standard deviation, " +
                     FormatPrintf("%.1f mm",
                                  1000.0 * f.camera_height_stddev_m) +
                     ", includes)")
               : std::string())
       << ". Green dashed: the odometry frame's "
          "origin, --odometry_height_m above the floor. Status: "
       << EscapeMarkup(ToString(f.status))
       << (f.reason.empty() ? "" : " (" + EscapeMarkup(f.reason) + ")")
       << ".</figcaption>\n</figure>\n";
  return html.str();
}

}  // namespace odomcal
