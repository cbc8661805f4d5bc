// Quantities CalibrationResult::observability does not call estimated are
// written as null (JSON) or left out (YAML), and printed as "undetermined":
// a number the data do not support is never reported as if it were an
// estimate. A held translation z is the given value, written as such.

#include "odomcal/plugin/report/calibration_report.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/plugin/options/cli_flags.h"
#include "odomcal/plugin/report/floor_plane_report.h"
#include "odomcal/plugin/report/repeatability_report.h"
#include "odomcal/plugin/report/robot_outputs.h"
#include "odomcal/plugin/report/systematics_report.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"
#include "odomcal/solver/rigid3.h"

#include <opencv2/core.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

namespace odomcal {
namespace {

using nlohmann::json;

bool Estimated(Determination determination) {
  return determination == Determination::kEstimated;
}

bool ScaleDetermined(const CalibrationResult& result, size_t segment) {
  return result.has_estimate && result.observability.ScaleDetermined(segment) &&
         std::isfinite(result.metric_scales[segment]);
}

json NumberOrNull(double value, bool determined) {
  return determined && std::isfinite(value) ? json(value) : json(nullptr);
}

json PlanarityToJson(const PlanarityCheck& p) {
  if (!p.checked) return {{"checked", false}};
  return {
      {"checked", true},
      {"consistent", p.consistent},
      {"named", p.named},
      {"tilt_deg", p.tilt_deg},
      {"out_of_plane_m", p.out_of_plane_m},
      {"tilt_rms_deg", p.tilt_rms_deg},
      {"tilt_max_deg", p.tilt_max_deg},
      {"out_of_plane_rms_m", p.out_of_plane_rms_m},
      {"out_of_plane_max_m", p.out_of_plane_max_m},
      {"chi_square", p.chi_square},
      {"degrees_of_freedom", p.degrees_of_freedom},
      {"chi_square_threshold", p.chi_square_threshold},
      {"reduced_chi_square", p.reduced_chi_square},
      {"correlation_length", p.correlation_length},
      {"covariance_inflation", p.covariance_inflation},
      {"worst_first_time_s", FormatTimestampSeconds(p.worst_first_stamp_ns)},
      {"worst_last_time_s", FormatTimestampSeconds(p.worst_last_stamp_ns)},
      {"worst_tilt_rms_deg", p.worst_tilt_rms_deg},
      {"worst_out_of_plane_rms_m", p.worst_out_of_plane_rms_m},
      {"ground_tilt",
       {{"tested", p.ground_tested},
        {"windows", p.ground_windows},
        {"f_statistic", p.ground_f_statistic},
        {"f_threshold", p.ground_f_threshold},
        {"seen", p.ground_tilt_seen},
        {"roll_rms_deg", p.ground_roll_rms_deg},
        {"pitch_rms_deg", p.ground_pitch_rms_deg},
        {"named", p.ground_named}}},
  };
}

json ScaleDriftToJson(const ScaleDriftTerm& term) {
  const auto stddevs = [](const Eigen::Matrix<double, 5, 1>& v) {
    return json{{"rx_deg", v(0)},
                {"ry_deg", v(1)},
                {"rz_deg", v(2)},
                {"x_m", v(3)},
                {"y_m", v(4)}};
  };
  json out = {{"estimated", term.rate.estimated},
              {"num_pairs", term.rate.num_pairs},
              {"num_segments", term.rate.num_segments},
              {"rate_per_s", term.rate.rate_per_s},
              {"scatter_factor", term.rate.scatter_factor},
              {"likelihood_ratio", term.rate.likelihood_ratio},
              {"applied", term.applied},
              {"named", term.named}};
  if (term.applied) {
    out["stddev_before"] = stddevs(term.stddev_before);
    out["stddev_after"] = stddevs(term.stddev_after);
  }
  return out;
}

json DiagnosticsToJson(const CalibrationDiagnostics& d) {
  json out;
  out["num_pairs_in"] = d.num_pairs_in;
  out["num_pairs_used"] = d.num_pairs_used;
  json mask = json::array();
  for (const char used : d.inlier_mask) mask.push_back(used != 0);
  out["inlier_mask"] = mask;
  out["num_pairs_per_segment"] = d.num_pairs_per_segment;
  out["excitation"] = {
      {"yaw_increment_min_deg", d.yaw_increment_min_deg},
      {"yaw_increment_max_deg", d.yaw_increment_max_deg},
      {"yaw_increment_stddev_deg", d.yaw_increment_stddev_deg},
      {"num_rotating_pairs", d.num_rotating_pairs},
      {"num_left_turns", d.num_left_turns},
      {"num_right_turns", d.num_right_turns},
  };
  out["angle_consistency"] = {
      {"angle_mismatch_deg", d.angle_mismatch_deg},
      {"num_angle_mismatches", d.num_angle_mismatches},
  };
  out["conditioning"] = {
      {"rotation_step_eigenvalues",
       {d.rotation_step_eigenvalues(0),
        d.rotation_step_eigenvalues(1),
        d.rotation_step_eigenvalues(2),
        d.rotation_step_eigenvalues(3)}},
      {"rotation_step_ratio", d.rotation_step_ratio},
      {"rotation_step_gimbal", d.rotation_step_gimbal},
      {"translation_step_condition_number",
       NumberOrNull(d.translation_step_condition_number, true)},
  };
  out["residuals"] = {
      {"rotation_deg", d.rotation_residual_deg},
      {"translation_m", d.translation_residual_m},
      {"rms_rotation_deg", d.rms_rotation_residual_deg},
      {"max_rotation_deg", d.max_rotation_residual_deg},
      {"rms_translation_m", d.rms_translation_residual_m},
      {"max_translation_m", d.max_translation_residual_m},
      {"relative_translation", d.relative_translation_residual},
      {"reduced_chi_square", d.reduced_chi_square},
  };
  out["planarity"] = PlanarityToJson(d.planarity);
  out["scale_drift"] = ScaleDriftToJson(d.scale_drift);
  out["ransac_num_iterations"] = d.ransac_num_iterations;
  out["refined"] = d.refined;
  out["refinement_num_iterations"] = d.refinement_num_iterations;
  out["refinement_report"] = d.refinement_report;
  return out;
}

// The estimated noise under the keys of options.noise, and per group its
// ratio to the given noise and how it was determined.
json NoiseToJson(const NoiseEstimate& estimate) {
  const NoiseModel& n = estimate.noise;
  json groups = json::array();
  for (int g = 0; g < kNumNoiseGroups; ++g) {
    json tied = json::array();
    for (int h = 0; h < kNumNoiseGroups; ++h) {
      if (h != g && estimate.estimated[g] && estimate.estimated[h] &&
          estimate.tie[h] == estimate.tie[g]) {
        tied.push_back(ToString(static_cast<NoiseGroup>(h)));
      }
    }
    groups.push_back({
        {"group", ToString(static_cast<NoiseGroup>(g))},
        {"estimated", estimate.estimated[g]},
        {"sigma_ratio", estimate.SigmaRatio(static_cast<NoiseGroup>(g))},
        {"tied_with", tied},
        {"redundancy", estimate.redundancy[g]},
    });
  }
  json components = json::array();
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    if (!estimate.component_present[c]) continue;
    json tied = json::array();
    for (int d = 0; d < kNumNoiseComponents; ++d) {
      if (d != c && estimate.component_estimated[c] &&
          estimate.component_estimated[d] &&
          estimate.component_tie[d] == estimate.component_tie[c]) {
        tied.push_back(ToString(static_cast<NoiseComponent>(d)));
      }
    }
    components.push_back({
        {"component", ToString(static_cast<NoiseComponent>(c))},
        {"estimated", estimate.component_estimated[c]},
        {"sigma_ratio", estimate.SigmaRatio(static_cast<NoiseComponent>(c))},
        {"tied_with", tied},
        {"bound", ToString(estimate.component_bound[c])},
    });
  }
  return {
      {"odom_yaw_sigma_deg", n.odom_yaw_sigma_deg},
      {"odom_yaw_sigma_rel", n.odom_yaw_sigma_rel},
      {"odom_tilt_sigma_deg", n.odom_tilt_sigma_deg},
      {"odom_translation_sigma_m", n.odom_translation_sigma_m},
      {"odom_translation_sigma_rel", n.odom_translation_sigma_rel},
      {"cam_rotation_sigma_deg", n.cam_rotation_sigma_deg},
      {"cam_translation_sigma_rel", n.cam_translation_sigma_rel},
      {"num_pairs", estimate.num_pairs},
      {"groups", groups},
      {"cam_translation_along_sigma_rel", n.CamTranslationAlongSigmaRel()},
      {"components", components},
      {"stddev_widening", estimate.stddev_widening},
      {"misfit_widening", estimate.misfit_widening},
  };
}

}  // namespace

json TransformToJson(const Rigid3d& transform,
                     bool rotation_determined,
                     bool x_determined,
                     bool y_determined,
                     bool z_determined) {
  json out;
  if (!rotation_determined) {
    out["matrix"] = nullptr;
    out["quaternion_wxyz"] = nullptr;
    out["roll_pitch_yaw_deg"] = nullptr;
  } else {
    const Eigen::Matrix4d m = transform.ToMatrix();
    json rows = json::array();
    for (int r = 0; r < 4; ++r) {
      rows.push_back({m(r, 0), m(r, 1), m(r, 2), m(r, 3)});
    }
    out["matrix"] = rows;
    const Eigen::Quaterniond q = WithPositiveScalar(transform.rotation);
    out["quaternion_wxyz"] = {q.w(), q.x(), q.y(), q.z()};
    const Eigen::Vector3d rpy = RollPitchYaw(q) * kRadToDeg;
    out["roll_pitch_yaw_deg"] = {rpy.x(), rpy.y(), rpy.z()};
  }
  out["translation_m"] = {
      NumberOrNull(transform.translation.x(), x_determined),
      NumberOrNull(transform.translation.y(), y_determined),
      NumberOrNull(transform.translation.z(), z_determined)};
  return out;
}

// The held z as a prior; null when z is estimated or held exactly.
json TranslationZPriorToJson(const CalibrationResult& result) {
  const TranslationZPrior& prior = result.translation_z_prior;
  if (!prior.used || !result.has_estimate) return nullptr;
  return {
      {"held_m", prior.held_m},
      {"prior_stddev_m", prior.prior_stddev_m},
      {"moved_by_data", prior.moved_by_data},
      {"estimate_m", prior.estimate_m},
      {"stddev_m", prior.stddev_m},
      {"data_stddev_m",
       NumberOrNull(prior.data_stddev_m, std::isfinite(prior.data_stddev_m))},
  };
}

json CalibrationToJson(const CalibrationResult& result,
                       const ReportContext& context) {
  const Observability& observability = result.observability;
  const bool estimate = result.has_estimate;
  const bool rotation = estimate && Estimated(observability.rotation);
  const bool x = estimate && Estimated(observability.translation_x);
  const bool y = estimate && Estimated(observability.translation_y);
  const bool z = estimate && Estimated(observability.translation_z);
  json out;
  out["schema"] = "odomcal.calibration";
  out["schema_version"] = kResultSchemaVersion;
  out["status"] = ToString(result.status);
  out["message"] = result.message;
  out["conventions"] = {
      {"odom_from_cam", "x_in_odom = odom_from_cam * x_in_cam"},
      {"quaternion", "Hamilton, order w, x, y, z"},
      {"roll_pitch_yaw", "R = Rz(yaw) * Ry(pitch) * Rx(roll), degrees"},
      {"metric_scale", "metres per reconstruction unit"},
  };
  if (estimate) {
    out["odom_from_cam"] =
        TransformToJson(result.odom_from_cam, rotation, x, y, true);
    // The inverse depends on every component; it is given only when all
    // observable parts are determined (z is the fixed value).
    out["cam_from_odom"] =
        rotation && x && y
            ? TransformToJson(
                  Inverse(result.odom_from_cam), true, true, true, true)
            : json(nullptr);
  } else {
    out["odom_from_cam"] = nullptr;
    out["cam_from_odom"] = nullptr;
  }
  json scales = json::array();
  for (size_t k = 0; k < result.metric_scales.size(); ++k) {
    scales.push_back(
        NumberOrNull(result.metric_scales[k], ScaleDetermined(result, k)));
  }
  out["metric_scales"] = scales;
  out["metric_scale"] = scales.size() == 1 ? scales[0] : json(nullptr);
  out["unobservable"] = UnobservableNames(observability);
  out["fixed"] = {
      {"translation_z_m", context.calibration_options.fixed_translation_z_m}};

  if (result.covariance) {
    const Eigen::MatrixXd& c = *result.covariance;
    json stddev_scales = json::array();
    for (size_t k = 0; k < result.stddev_metric_scales_rel.size(); ++k) {
      stddev_scales.push_back(NumberOrNull(result.stddev_metric_scales_rel[k],
                                           ScaleDetermined(result, k)));
    }
    out["stddev"] = {
        {"roll_deg",
         NumberOrNull(result.stddev_roll_pitch_yaw_deg.x(), rotation)},
        {"pitch_deg",
         NumberOrNull(result.stddev_roll_pitch_yaw_deg.y(), rotation)},
        {"yaw_deg",
         NumberOrNull(result.stddev_roll_pitch_yaw_deg.z(), rotation)},
        {"rotation_axes_deg",
         {NumberOrNull(result.stddev_rotation_axes_deg.x(), rotation),
          NumberOrNull(result.stddev_rotation_axes_deg.y(), rotation),
          NumberOrNull(result.stddev_rotation_axes_deg.z(), rotation)}},
        {"translation_x_m",
         NumberOrNull(result.stddev_translation_xy_m.x(), x)},
        {"translation_y_m",
         NumberOrNull(result.stddev_translation_xy_m.y(), y)},
        {"translation_z_m", NumberOrNull(result.stddev_translation_z_m, z)},
        {"metric_scales_rel", stddev_scales},
    };
    // tz, when estimated or under its prior, is the last parameter.
    const bool tz =
        result.observability.translation_z == Determination::kEstimated ||
        result.translation_z_prior.moved_by_data;
    json order = {"rx", "ry", "rz", "tx", "ty"};
    // Scale rows are labelled with their segment: a segment without used
    // pairs has none.
    for (size_t k = 0; k + 5 + tz < static_cast<size_t>(c.rows()); ++k) {
      const int segment = k < result.covariance_segments.size()
                              ? result.covariance_segments[k]
                              : static_cast<int>(k);
      order.push_back("s_" + std::to_string(segment));
    }
    if (tz) order.push_back("tz");
    json rows = json::array();
    for (int r = 0; r < c.rows(); ++r) {
      json row = json::array();
      for (int col = 0; col < c.cols(); ++col) row.push_back(c(r, col));
      rows.push_back(row);
    }
    out["covariance"] = {
        {"order", order},
        {"perturbation",
         "rotation: left, R = Exp(phi) * R_hat, phi in radians about the "
         "odometry axes; translation: additive, metres; s_k: metric scale of "
         "segment k, metres per reconstruction unit; " +
             std::string(tz ? "tz: translation z, additive, metres"
                            : "translation z is fixed and excluded")},
        {"matrix", rows},
    };
  } else {
    out["stddev"] = nullptr;
    out["covariance"] = nullptr;
  }
  if (result.noise_estimate)
    out["noise_estimated"] = NoiseToJson(*result.noise_estimate);
  out["translation_z_source"] = ToString(observability.translation_z_source);
  out["translation_z_prior"] = TranslationZPriorToJson(result);
  out["floor_plane"] = FloorPlaneToJson(result);
  out["warnings"] = result.warnings;
  json diagnostics = DiagnosticsToJson(result.diagnostics);
  const AssociationResult& a = context.association;
  diagnostics["association"] = {
      {"num_camera_poses", a.num_camera_poses},
      {"num_usable_camera_poses", a.num_usable_camera_poses},
      {"num_outside_odometry_span", a.num_outside_odometry_span},
      {"num_in_odometry_gaps", a.num_in_odometry_gaps},
      {"num_keyframes", a.num_keyframes},
      {"num_pairs_per_segment", a.num_pairs_per_segment},
      {"odometry_rate_hz", a.odometry_rate_hz},
  };
  if (a.keyframe_spacing_automatic) {
    const CameraPoseDriftTest& drift = a.camera_pose_drift;
    diagnostics["association"]["camera_pose_drift"] = {
        {"decided", drift.decided},
        {"drifting", drift.drifting},
        {"span", drift.span},
        {"num_pairs", drift.num_pairs},
        {"rotation_ratio", drift.rotation_ratio},
        {"translation_ratio", drift.translation_ratio},
        {"threshold", drift.threshold},
    };
    diagnostics["association"]["keyframe_min_span_s"] = a.keyframe_min_span_s;
  }
  if (result.has_estimate) {
    const CalibrationDiagnostics& d = result.diagnostics;
    json linear_scales = json::array();
    for (const double s : d.linear_metric_scales)
      linear_scales.push_back(NumberOrNull(s, true));
    diagnostics["closed_form"] = {
        {"odom_from_cam",
         TransformToJson(d.linear_odom_from_cam, rotation, x, y, true)},
        {"metric_scales", linear_scales},
    };
  }
  out["diagnostics"] = diagnostics;
  if (context.systematics) AddSystematicsJson(*context.systematics, &out);
  out["robot"] = RobotToJson(RobotDescriptionOf(result, context));
  out["repeatability"] = RepeatabilityToJson(context.repeatability);
  // The paths and units as read, then the flags' values from the option
  // tables (ReportContext::flag_echo; by default those of the options the
  // context holds).
  json inputs = {
      {"command", context.command},
      {"camera_poses", context.camera_paths},
      {"camera_pose_convention",
       "TUM: timestamp tx ty tz qx qy qz qw, world_from_cam"},
      {"odometry", context.odometry_path},
      {"odometry_format", OdometryFormatName(context.odometry_format)},
      {"camera_time_unit", context.camera_time_unit},
      {"odometry_time_unit", context.odometry_time_unit},
  };
  const json flag_echo = context.flag_echo.is_null()
                             ? CalibrationFlagsEcho(context.association_options,
                                                    context.calibration_options,
                                                    context.systematics_options,
                                                    context.robot_frames)
                             : context.flag_echo;
  inputs.update(flag_echo.value("inputs", json::object()));
  if (context.association.max_odometry_gap_s > 0.0) {
    // The gap limit used, and whether it came from the odometry's sampling.
    inputs["max_odometry_gap_s"] = context.association.max_odometry_gap_s;
    inputs["max_odometry_gap_automatic"] =
        context.association.max_odometry_gap_automatic;
  }
  if (context.association.keyframe_spacing_automatic) {
    // The keyframe thresholds used, and that the camera poses chose them.
    inputs["keyframe_min_rotation_deg"] =
        context.association.keyframe_min_rotation_deg;
    inputs["keyframe_min_translation_m"] =
        context.association.keyframe_min_translation_m;
    inputs["keyframe_spacing_automatic"] = true;
  }
  const json options = flag_echo.value("options", json::object());
  out["inputs"] = inputs;
  out["options"] = options;
  return out;
}

std::string CalibrationToYaml(const CalibrationResult& result) {
  cv::FileStorage fs(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY);
  fs << "status" << ToString(result.status);
  fs << "message" << result.message;
  const Observability& observability = result.observability;
  const bool rotation =
      result.has_estimate && Estimated(observability.rotation);
  const bool x = result.has_estimate && Estimated(observability.translation_x);
  const bool y = result.has_estimate && Estimated(observability.translation_y);
  if (rotation && x && y) {
    const Eigen::Matrix4d m = result.odom_from_cam.ToMatrix();
    cv::Mat matrix(4, 4, CV_64F);
    for (int r = 0; r < 4; ++r) {
      for (int c = 0; c < 4; ++c) matrix.at<double>(r, c) = m(r, c);
    }
    fs << "odom_from_cam" << matrix;
    const Eigen::Quaterniond q =
        WithPositiveScalar(result.odom_from_cam.rotation);
    fs << "quaternion_wxyz" << std::vector<double>{q.w(), q.x(), q.y(), q.z()};
    const Eigen::Vector3d& t = result.odom_from_cam.translation;
    fs << "translation_m" << std::vector<double>{t.x(), t.y(), t.z()};
  }
  std::vector<double> scales;
  for (size_t k = 0; k < result.metric_scales.size(); ++k) {
    if (!ScaleDetermined(result, k)) {
      scales.clear();
      break;
    }
    scales.push_back(result.metric_scales[k]);
  }
  if (!scales.empty()) fs << "metric_scales" << scales;
  fs << "unobservable"
     << "[";
  for (const std::string& name : UnobservableNames(observability)) fs << name;
  fs << "]";
  if (result.covariance && rotation && x && y) {
    const Eigen::MatrixXd& c = *result.covariance;
    cv::Mat covariance(
        static_cast<int>(c.rows()), static_cast<int>(c.cols()), CV_64F);
    for (int r = 0; r < c.rows(); ++r) {
      for (int col = 0; col < c.cols(); ++col) {
        covariance.at<double>(r, col) = c(r, col);
      }
    }
    fs << "covariance" << covariance;
    fs << "covariance_order"
       << (Estimated(observability.translation_z) ||
                   result.translation_z_prior.moved_by_data
               ? "rx ry rz (left perturbation, rad) tx ty (m) s_k tz (m)"
               : "rx ry rz (left perturbation, rad) tx ty (m) s_k");
  }
  return fs.releaseAndGetString();
}

std::string AssociationSummary(const AssociationResult& a) {
  std::ostringstream out;
  out << std::setprecision(3) << a.num_camera_poses
      << " camera poses: " << a.num_usable_camera_poses << " used, "
      << a.num_outside_odometry_span << " outside the odometry's span, "
      << a.num_in_odometry_gaps << " in its gaps (> " << a.max_odometry_gap_s
      << " s" << (a.max_odometry_gap_automatic ? ", automatic" : "")
      << "); odometry at " << a.odometry_rate_hz << " Hz; " << a.num_keyframes
      << " keyframes, " << a.pairs.size() << " motion pairs";
  return out.str();
}

std::string KeyframeSpacingSummary(const AssociationResult& a) {
  if (!a.keyframe_spacing_automatic) return "";
  const CameraPoseDriftTest& drift = a.camera_pose_drift;
  std::ostringstream out;
  out << std::setprecision(3) << "every " << a.keyframe_min_rotation_deg
      << " deg / " << a.keyframe_min_translation_m << " m of odometry motion, "
      << a.keyframe_min_span_s << " s apart at least (automatic): ";
  if (!drift.decided) {
    out << "the camera poses were not tested for drift (fewer than "
        << CameraPoseDriftOptions().min_num_pairs
        << " pairs of poses, exact poses or motion off the plane)";
  } else {
    out << "the camera poses " << (drift.drifting ? "drift" : "do not drift")
        << " (their error across the plane of motion over " << drift.span
        << " frames is " << drift.rotation_ratio << "x in rotation and "
        << drift.translation_ratio << "x in translation that over one; "
        << "drift from " << drift.threshold << "x)";
  }
  return out.str();
}

std::string CalibrationSummary(const CalibrationResult& result,
                               const ReportContext& context) {
  std::ostringstream out;
  // A refusal must not read like a result: it says so first, and whatever
  // it estimated is labelled as not a calibration.
  const bool calibrated = result.IsSuccess();
  if (calibrated) {
    out << context.command << ": " << ToString(result.status) << " - "
        << result.message << "\n";
  } else {
    out << context.command << ": not a calibration (" << ToString(result.status)
        << "): " << result.message << "\n";
  }
  const AssociationResult& a = context.association;
  out << "  input: " << AssociationSummary(a) << "\n";
  if (a.keyframe_spacing_automatic) {
    out << "  keyframes: " << KeyframeSpacingSummary(a) << "\n";
  }
  if (!result.has_estimate) {
    out << "  no estimate; undetermined:";
    for (const std::string& name : UnobservableNames(result.observability)) {
      out << " " << name;
    }
    out << "\n";
  } else {
    const Observability& o = result.observability;
    const bool sigma = result.covariance.has_value();
    const bool rotation = Estimated(o.rotation);
    if (calibrated) {
      out << "  odom_from_cam (x_in_odom = odom_from_cam * x_in_cam):\n";
    } else {
      out << "  undetermined:";
      for (const std::string& name : UnobservableNames(o)) out << " " << name;
      out << "\n  partial estimate, NOT a calibration (do not use it; "
             "odom_from_cam, x_in_odom = odom_from_cam * x_in_cam):\n";
    }
    if (rotation) {
      const Eigen::Vector3d rpy =
          RollPitchYaw(result.odom_from_cam.rotation) * kRadToDeg;
      const char* names[3] = {"roll ", "pitch", "yaw  "};
      for (int k = 0; k < 3; ++k) {
        out << "    " << names[k] << " " << FormatPrintf("%10.4f deg", rpy(k));
        if (sigma) {
          out << FormatPrintf("  +- %.4f deg (3 sigma)",
                              3.0 * result.stddev_roll_pitch_yaw_deg(k));
        }
        out << "\n";
      }
      const Eigen::Quaterniond q =
          WithPositiveScalar(result.odom_from_cam.rotation);
      out << "    quaternion wxyz [" << FormatPrintf("%.6f", q.w()) << ", "
          << FormatPrintf("%.6f", q.x()) << ", " << FormatPrintf("%.6f", q.y())
          << ", " << FormatPrintf("%.6f", q.z()) << "]\n";
    } else {
      out << "    rotation   undetermined\n";
    }
    const char axis[2] = {'x', 'y'};
    for (int k = 0; k < 2; ++k) {
      out << "    " << axis[k] << "     ";
      if (!Estimated(k == 0 ? o.translation_x : o.translation_y)) {
        out << "undetermined\n";
        continue;
      }
      out << FormatPrintf("%10.2f cm",
                          100.0 * result.odom_from_cam.translation(k));
      if (sigma) {
        out << FormatPrintf("   +- %.2f cm (3 sigma)",
                            300.0 * result.stddev_translation_xy_m(k));
      }
      out << "\n";
    }
    out << "    z     "
        << FormatPrintf("%10.2f cm",
                        100.0 * result.odom_from_cam.translation.z());
    if ((Estimated(o.translation_z) ||
         result.translation_z_prior.moved_by_data) &&
        sigma) {
      out << FormatPrintf("   +- %.2f cm (3 sigma)",
                          300.0 * result.stddev_translation_z_m);
    }
    out << "   " << TranslationZOrigin(result) << "\n";
    for (size_t k = 0; k < result.metric_scales.size(); ++k) {
      out << "  metric scale";
      if (result.metric_scales.size() > 1) out << " [segment " << k << "]";
      if (!ScaleDetermined(result, k)) {
        out << " undetermined\n";
        continue;
      }
      out << FormatPrintf(" %.6f m/unit", result.metric_scales[k]);
      if (sigma && k < result.stddev_metric_scales_rel.size()) {
        out << FormatPrintf("  +- %.3f %% (3 sigma)",
                            300.0 * result.stddev_metric_scales_rel[k]);
      }
      out << "\n";
    }
    const CalibrationDiagnostics& d = result.diagnostics;
    out << "  pairs used " << d.num_pairs_used << " of " << d.num_pairs_in
        << "; residuals rms "
        << FormatPrintf("%.3f deg", d.rms_rotation_residual_deg) << ", "
        << FormatPrintf("%.1f mm", 1000.0 * d.rms_translation_residual_m)
        << "; yaw increments " << FormatPrintf("%.1f", d.yaw_increment_min_deg)
        << " .. " << FormatPrintf("%.1f deg", d.yaw_increment_max_deg) << "\n";
    if (result.noise_estimate) {
      out << "  " << NoiseSummary(*result.noise_estimate) << "\n";
    }
    out << FloorPlaneSummary(result);
  }
  if (context.systematics) out << SystematicsSummary(*context.systematics);
  if (context.repeatability) {
    out << RepeatabilitySummary(*context.repeatability);
  }
  if (const auto robot = RobotDescriptionOf(result, context)) {
    out << RobotSummary(*robot);
  }
  for (const std::string& warning : result.warnings) {
    out << "  warning: " << warning << "\n";
  }
  return out.str();
}

}  // namespace odomcal
