#include "odomcal/plugin/report/joint_adjustment_report.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/plugin/report/svg_plot.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <sstream>

namespace odomcal {

using nlohmann::json;

namespace {

bool Succeeded(const JointAdjustmentRun& joint) {
  return joint.ran && joint.result.IsSuccess();
}

// The values in `format` each, joined by " / ".
std::string Joined(const char* format, std::initializer_list<double> values) {
  std::string text;
  for (const double value : values) {
    text += (text.empty() ? "" : " / ") + FormatPrintf(format, value);
  }
  return text;
}

bool IsAngle(const ExtrinsicDisagreement& disagreement) {
  return disagreement.quantity.find("translation") == std::string::npos;
}

}  // namespace

json JointCameraIntrinsicsToJson(const std::vector<JointCamera>& before,
                                 bool refine_intrinsics,
                                 const std::vector<JointCamera>& after) {
  json out = json::array();
  for (size_t c = 0; c < before.size() && c < after.size(); ++c) {
    out.push_back({{"model", ProjectionModelName(after[c].model)},
                   {"refined", refine_intrinsics && !before[c].held},
                   {"params_before", before[c].params},
                   {"params", after[c].params}});
  }
  return out;
}

json JointAdjustmentToJson(const ColmapCalibrationRun& run) {
  const JointAdjustmentRun& joint = run.joint;
  if (!joint.requested) return nullptr;
  if (!joint.ran) {
    return {{"status", "skipped"},
            {"message",
             joint.skipped.empty() ? "no extrinsic to adjust" : joint.skipped}};
  }
  const JointAdjustmentResult& r = joint.result;
  json out = {
      {"status", ToString(r.status)},
      {"message", r.message},
      {"use", ToString(joint.use)},
      {"adopted", joint.adopted},
      {"num_images", joint.num_images},
      {"num_points", joint.num_points},
      {"num_odometry_links", joint.num_links},
      {"num_joining_links", joint.num_joining_links},
  };
  if (!r.IsSuccess()) return out;
  out["max_disagreement_sigmas"] = joint.max_disagreement_sigmas;
  out["max_disagreement_sigmas_jackknifed"] =
      joint.max_disagreement_sigmas_jackknifed >= 0.0
          ? json(joint.max_disagreement_sigmas_jackknifed)
          : json(nullptr);
  out["contradiction_sigmas"] = kJointContradictionSigmas;
  json disagreements = json::array();
  for (const ExtrinsicDisagreement& d : joint.disagreements) {
    disagreements.push_back({{"quantity", d.quantity},
                             {"difference", d.difference},
                             {"two_step_stddev", d.two_step_stddev},
                             {"joint_stddev", d.joint_stddev},
                             {"unit", IsAngle(d) ? "deg" : "m"}});
  }
  json stretches = json::array();
  for (const JointStretchScale& s : joint.stretches) {
    stretches.push_back(
        {{"metric_model", s.metric_model},
         {"first_time_s", FormatTimestampSeconds(s.first_stamp_ns)},
         {"last_time_s", FormatTimestampSeconds(s.last_stamp_ns)},
         {"num_images", s.num_images},
         {"path_length_m", s.path_length_m},
         {"two_step_metric_scale", s.two_step_scale},
         {"joint_metric_scale", s.joint_scale}});
  }
  out["num_components"] = r.num_components;
  out["num_observations_used"] = r.num_observations_used;
  out["num_observations_left_out"] = r.num_observations_left_out;
  out["pixel_sigma_px"] = r.pixel_sigma;
  out["odometry_sigma_ratio"] = r.odometry_sigma_ratio;
  out["robot_poses"] = ToString(r.motion_model);
  out["max_robot_tilt_deg"] = r.max_robot_tilt_deg;
  out["ground_tilt_rate_deg_per_m"] =
      r.motion_model == RobotMotionModel::kOnGround
          ? json(r.ground_tilt_rate_deg_per_m)
          : json(nullptr);
  out["camera_intrinsics"] = JointCameraIntrinsicsToJson(
      joint.cameras_before, joint.refine_intrinsics, r.cameras);
  out["covariance_widening"] = {r.covariance_widening[0],
                                r.covariance_widening[1],
                                r.covariance_widening[2],
                                r.covariance_widening[3],
                                r.covariance_widening[4]};
  if (joint.refined_systematics) {
    out["systematics"] = {
        {"time_offset_change_s", r.time_offset_change_s},
        {"time_offset_change_stddev_s", r.time_offset_change_stddev_s},
        {"yaw_scale", r.intrinsics.yaw_scale},
        {"yaw_per_metre_rad", r.intrinsics.yaw_per_metre_rad},
        {"yaw_rate_bias_rad_s", r.intrinsics.yaw_rate_bias_rad_s},
        {"intrinsics_stddev",
         {r.intrinsics_stddev[0],
          r.intrinsics_stddev[1],
          r.intrinsics_stddev[2]}}};
  } else {
    out["systematics"] = nullptr;
  }
  const JointJackknife& jackknife = joint.jackknife;
  out["jackknife"] = {
      {"ran", jackknife.ran},
      {"reason", jackknife.ran ? json(nullptr) : json(jackknife.reason)},
      {"num_blocks", jackknife.num_blocks},
      {"stddev_ratio",
       jackknife.ran ? json{jackknife.ratio[0],
                            jackknife.ratio[1],
                            jackknife.ratio[2],
                            jackknife.ratio[3],
                            jackknife.ratio[4]}
                     : json(nullptr)},
      {"time_s", jackknife.time_s}};
  out["reprojection_rms_px"] = {{"before", r.reprojection_rms_px_before},
                                {"after", r.reprojection_rms_px_after}};
  out["odometry_rms_sigma"] = {{"before", r.odometry_rms_sigma_before},
                               {"after", r.odometry_rms_sigma_after}};
  out["num_iterations"] = r.num_iterations;
  out["time_s"] = r.solve_time_s + r.covariance_time_s + jackknife.time_s;
  out["covariance_time_s"] = r.covariance_time_s;
  out["disagreements"] = disagreements;
  out["stretches"] = stretches;
  out["max_scale_change"] = joint.max_scale_change;
  return out;
}

json TwoStepToJson(const ColmapCalibrationRun& run) {
  const JointAdjustmentRun& joint = run.joint;
  if (!Succeeded(joint) || !joint.adopted) return nullptr;
  const Eigen::Matrix3d rpy =
      RollPitchYawJacobian(joint.two_step_odom_from_cam.rotation);
  const Eigen::Vector3d rpy_stddev =
      (rpy * joint.two_step_covariance.topLeftCorner<3, 3>() * rpy.transpose())
          .diagonal()
          .cwiseSqrt() *
      kRadToDeg;
  return {
      {"odom_from_cam",
       TransformToJson(joint.two_step_odom_from_cam, true, true, true, true)},
      {"stddev",
       {{"roll_deg", rpy_stddev.x()},
        {"pitch_deg", rpy_stddev.y()},
        {"yaw_deg", rpy_stddev.z()},
        {"translation_x_m", std::sqrt(joint.two_step_covariance(3, 3))},
        {"translation_y_m", std::sqrt(joint.two_step_covariance(4, 4))}}}};
}

std::string JointAdjustmentSummary(const ColmapCalibrationRun& run) {
  const JointAdjustmentRun& joint = run.joint;
  const bool check = joint.use == JointAdjustmentUse::kCheck;
  const char* const name =
      check ? "joint adjustment check" : "joint adjustment";
  const char* const stands = check ? "the two-step result stands, unchecked"
                                   : "the two-step result stands";
  if (!joint.ran) {
    // A check of a calibration without an estimate has nothing to say.
    if (!joint.requested || joint.skipped.empty() ||
        (check && !run.check.result.has_estimate)) {
      return "";
    }
    return std::string("  ") + name + ": not run (" + joint.skipped + "); " +
           stands + "\n";
  }
  std::ostringstream out;
  const JointAdjustmentResult& r = joint.result;
  if (!r.IsSuccess()) {
    out << "  " << name << ": " << ToString(r.status) << " (" << r.message
        << "); " << stands << "\n";
    return out.str();
  }
  if (!joint.adopted) {
    out << "  joint adjustment check: the two-step estimate stands (the "
           "adjustment differs by at most "
        << FormatPrintf("%.1f", joint.max_disagreement_sigmas)
        << " sigma of the difference";
    if (joint.max_disagreement_sigmas_jackknifed >= 0.0) {
      out << ", "
          << FormatPrintf("%.1f", joint.max_disagreement_sigmas_jackknifed)
          << " once its jackknife widened its own uncertainty";
    }
    out << ", a contradiction is more than "
        << FormatPrintf("%.0f", kJointContradictionSigmas) << "; "
        << joint.num_images << " images, " << joint.num_points << " points, "
        << joint.num_links << " odometry links; reprojection rms "
        << FormatPrintf("%.2f px", r.reprojection_rms_px_after) << "; "
        << FormatPrintf("%.1f s", r.solve_time_s + r.covariance_time_s)
        << "); --joint_adjustment on reports its estimate\n";
    return out.str();
  }
  out << "  joint adjustment: " << joint.num_images << " images, "
      << joint.num_points << " points, " << joint.num_links
      << " odometry links; reprojection rms "
      << FormatPrintf("%.2f", r.reprojection_rms_px_before) << " -> "
      << FormatPrintf("%.2f px", r.reprojection_rms_px_after)
      << ", odometry rms " << FormatPrintf("%.2f", r.odometry_rms_sigma_before)
      << " -> " << FormatPrintf("%.2f sigma", r.odometry_rms_sigma_after)
      << "; "
      << FormatPrintf(
             "%.1f s",
             r.solve_time_s + r.covariance_time_s + joint.jackknife.time_s)
      << "\n";
  const bool at_bound = r.odometry_sigma_ratio <= 0.1 + 1e-9 ||
                        r.odometry_sigma_ratio >= 10.0 - 1e-9;
  out << "  joint noise: pixel sigma " << FormatPrintf("%.3f px", r.pixel_sigma)
      << ", odometry " << FormatPrintf("x%.2g", r.odometry_sigma_ratio)
      << " the two-step's noise model" << (at_bound ? " (at its bound)" : "")
      << "\n";
  if (r.motion_model == RobotMotionModel::kOnGround) {
    out << "  joint robot poses: on the ground (a planar log: its x, y and "
           "yaw as measured, the tilt and height between images bounded by "
           "the ground's tilt rate, "
        << FormatPrintf("%.3f deg/m", r.ground_tilt_rate_deg_per_m)
        << " estimated); the robot tilted up to "
        << FormatPrintf("%.2f deg", r.max_robot_tilt_deg)
        << " from the first image's level\n";
  } else if (r.motion_model == RobotMotionModel::kSE3) {
    out << "  joint robot poses: SE(3) (a 3-D log); the robot tilted up to "
        << FormatPrintf("%.2f deg", r.max_robot_tilt_deg)
        << " from the first image's level\n";
  }
  if (joint.jackknife.ran) {
    const auto& w = r.covariance_widening;
    out << "  joint sigma widening (roll/pitch/yaw, x/y), from the tracks and "
        << "a jackknife over " << joint.jackknife.num_blocks
        << " stretches: " << Joined("%.2f", {w[0], w[1], w[2], w[3], w[4]})
        << "\n";
  }
  for (size_t c = 0; c < joint.cameras_before.size() && c < r.cameras.size();
       ++c) {
    if (!joint.refine_intrinsics || joint.cameras_before[c].held) continue;
    out << "  joint camera intrinsics refined (" +
               std::string(ProjectionModelName(r.cameras[c].model)) +
               "; the principal point held): focal length "
        << FormatPrintf("%.2f", joint.cameras_before[c].params[0]) << " -> "
        << FormatPrintf("%.2f px", r.cameras[c].params[0]) << "\n";
  }
  if (joint.intrinsics == JointIntrinsics::kAuto &&
      run.database_cameras.empty()) {
    out << "  joint camera intrinsics held as the model has them: without the "
           "database's cameras (--database_path) it is not known whether "
           "COLMAP's bundle adjustment changed them (--joint_intrinsics "
           "refined refines them)\n";
  }
  if (joint.refined_systematics) {
    out << "  joint systematics (3 sigma): clock offset changed by "
        << FormatPrintf("%+.2f", 1e3 * r.time_offset_change_s) << " +- "
        << FormatPrintf("%.2f ms", 3e3 * r.time_offset_change_stddev_s)
        << ", yaw_scale " << FormatPrintf("%.5f", r.intrinsics.yaw_scale)
        << " +- " << FormatPrintf("%.5f", 3.0 * r.intrinsics_stddev[0]) << "\n";
  }
  const Rigid3d& two_step = joint.two_step_odom_from_cam;
  const Eigen::Vector3d rpy = RollPitchYaw(two_step.rotation) * kRadToDeg;
  out << "  two-step estimate: roll/pitch/yaw "
      << Joined("%.3f", {rpy.x(), rpy.y(), rpy.z()}) << " deg, x/y "
      << Joined("%.4f", {two_step.translation.x(), two_step.translation.y()})
      << " m"
      << "; COLMAP scale drift taken out: up to "
      << FormatPrintf("%.2f %%", 100.0 * joint.max_scale_change) << "\n";
  return out.str();
}

std::string JointAdjustmentHtml(const ColmapCalibrationRun& run) {
  const JointAdjustmentRun& joint = run.joint;
  if (!joint.ran) return "";
  const JointAdjustmentResult& r = joint.result;
  std::ostringstream html;
  html << "<h2>Joint adjustment</h2>\n";
  if (r.IsSuccess() && !joint.adopted) {
    html
        << "<p>Run as a check of the two-step estimate: they differ by at "
           "most "
        << EscapeMarkup(FormatPrintf("%.1f", joint.max_disagreement_sigmas))
        << " standard deviations of their difference"
        << (joint.max_disagreement_sigmas_jackknifed >= 0.0
                ? EscapeMarkup(FormatPrintf(
                      ", %.1f once the adjustment's jackknife over stretches "
                      "of the drive widened its own uncertainty",
                      joint.max_disagreement_sigmas_jackknifed))
                : std::string())
        << " (a contradiction is more than "
        << EscapeMarkup(FormatPrintf("%.0f", kJointContradictionSigmas))
        << "), so the two-step estimate is reported. "
           "<code>--joint_adjustment on</code> reports the adjustment's.</p>\n";
    return html.str();
  }
  if (!r.IsSuccess()) {
    html << "<p>Not used: " << EscapeMarkup(ToString(r.status)) << " ("
         << EscapeMarkup(r.message)
         << "). The extrinsic and the metric model are the two-step "
            "calibration's.</p>\n";
    return html.str();
  }
  const Eigen::Vector3d rpy_two =
      RollPitchYaw(joint.two_step_odom_from_cam.rotation) * kRadToDeg;
  const Eigen::Vector3d rpy_joint =
      RollPitchYaw(r.odom_from_cam.rotation) * kRadToDeg;
  html << "<table>\n<tr><th></th><th>two-step</th><th>joint</th></tr>\n"
       << "<tr><td>roll / pitch / yaw [deg]</td><td>"
       << Joined("%.3f", {rpy_two.x(), rpy_two.y(), rpy_two.z()}) << "</td><td>"
       << Joined("%.3f", {rpy_joint.x(), rpy_joint.y(), rpy_joint.z()})
       << "</td></tr>\n<tr><td>x / y [mm]</td><td>"
       << Joined("%.1f",
                 {1e3 * joint.two_step_odom_from_cam.translation.x(),
                  1e3 * joint.two_step_odom_from_cam.translation.y()})
       << "</td><td>"
       << Joined("%.1f",
                 {1e3 * r.odom_from_cam.translation.x(),
                  1e3 * r.odom_from_cam.translation.y()})
       << "</td></tr>\n<tr><td>reprojection rms [px]</td><td>"
       << FormatPrintf("%.2f", r.reprojection_rms_px_before) << "</td><td>"
       << FormatPrintf("%.2f", r.reprojection_rms_px_after)
       << "</td></tr>\n<tr><td>odometry rms [sigma]</td><td>"
       << FormatPrintf("%.2f", r.odometry_rms_sigma_before) << "</td><td>"
       << FormatPrintf("%.2f", r.odometry_rms_sigma_after)
       << "</td></tr>\n<tr><td>stated sigma over the noise model's "
          "(roll, pitch, yaw, x, y)</td><td></td><td>"
       << Joined("%.2f",
                 {r.covariance_widening[0],
                  r.covariance_widening[1],
                  r.covariance_widening[2],
                  r.covariance_widening[3],
                  r.covariance_widening[4]})
       << (joint.jackknife.ran
               ? " (tracks; jackknife over " +
                     std::to_string(joint.jackknife.num_blocks) + " stretches)"
               : std::string(" (tracks)"))
       << "</td></tr>\n</table>\n";
  if (joint.stretches.empty()) return html.str();
  PlotFigure figure;
  figure.num_columns = 1;
  figure.panel_width_px = 900.0;
  figure.panel_height_px = 240.0;
  PlotPanel& panel = figure.panels.emplace_back();
  panel.title = "COLMAP's scale along the drive";
  panel.x_label = "time from the first stretch's start [s]";
  panel.y_label = "joint / two-step scale - 1 [%]";
  PlotSeries change{"per stretch", {}, {}, "#1f77b4", false, true, false};
  int64_t start_ns = joint.stretches.front().first_stamp_ns;
  for (const JointStretchScale& s : joint.stretches) {
    start_ns = std::min(start_ns, s.first_stamp_ns);
  }
  for (const JointStretchScale& s : joint.stretches) {
    // Stamps are epoch nanoseconds: the middle of the stretch, from the
    // start, in seconds.
    change.x.push_back(
        1e-9 * static_cast<double>(s.first_stamp_ns - start_ns) +
        0.5e-9 * static_cast<double>(s.last_stamp_ns - s.first_stamp_ns));
    change.y.push_back(100.0 * (s.joint_scale / s.two_step_scale - 1.0));
  }
  panel.series = {change};
  html << "<figure>\n"
       << RenderSvg(figure)
       << "<figcaption>Per stretch of the drive, the metric scale of the "
          "adjusted model (its camera path in metres over COLMAP's) against "
          "the one scale the two-step calibration gave the part: where COLMAP "
          "drifted, the adjustment follows the odometry and the images "
          "together. "
       << r.num_observations_left_out << " of "
       << r.num_observations_left_out + r.num_observations_used
       << " observations lay beyond the outlier gate and were left out; "
          "pixel sigma "
       << EscapeMarkup(FormatPrintf("%.2f px", r.pixel_sigma))
       << ".</figcaption>\n</figure>\n";
  return html.str();
}

}  // namespace odomcal
