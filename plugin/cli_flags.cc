#include "odomcal/plugin/cli_flags.h"

#include "odomcal/solver/format_number.h"

#include <cmath>
#include <stdexcept>

namespace odomcal {

void AddCalibrationFlags(CLI::App* app,
                         CalibrateInputs* inputs,
                         CalibrationFlags* flags) {
  CalibrationOptions& o = inputs->calibration;
  AssociationOptions& a = inputs->association;
  // Inputs and time.
  app->add_option(
         "--odometry_format", flags->odometry_format, "odometry file format")
      ->check(CLI::IsMember({"auto", "tum", "csv"}))
      ->capture_default_str();
  app->add_option("--camera_time_unit",
                  flags->camera_time_unit,
                  "unit of the camera timestamps")
      ->check(CLI::IsMember({"s", "ms", "us", "ns"}))
      ->capture_default_str();
  app->add_option("--odometry_time_unit",
                  flags->odometry_time_unit,
                  "unit of the odometry timestamps (a CSV header's time_ms "
                  "etc. sets it per file)")
      ->check(CLI::IsMember({"s", "ms", "us", "ns"}))
      ->capture_default_str()
      ->each([flags](const std::string&) {
        flags->odometry_time_unit_given = true;
      });
  app->add_option("--camera_time_offset_s",
                  flags->camera_time_offset_s,
                  "added to camera times to get odometry times")
      ->capture_default_str();
  app->add_option("--max_odometry_gap_s",
                  a.max_odometry_gap_s,
                  "camera times in odometry gaps longer than this are skipped")
      ->capture_default_str();
  app->add_option("--keyframe_min_rotation_deg",
                  a.keyframe_min_rotation_deg,
                  "next keyframe after this much odometry rotation...")
      ->capture_default_str();
  app->add_option("--keyframe_min_translation_m",
                  a.keyframe_min_translation_m,
                  "...or this much odometry translation")
      ->capture_default_str();
  // Method.
  app->add_option("--method", flags->method, "closed form")
      ->check(CLI::IsMember({"alsp", "als"}))
      ->capture_default_str();
  app->add_option("--alsp_projection",
                  flags->alsp_projection,
                  "ALSP projection of camera translations onto the plane")
      ->check(CLI::IsMember({"orthogonal", "length_preserving"}))
      ->capture_default_str();
  app->add_flag("--no_refine",
                flags->no_refine,
                "report the closed form without Ceres refinement");
  app->add_option("--fixed_translation_z_m",
                  o.fixed_translation_z_m,
                  "z of the camera in the odometry frame (unobservable under "
                  "planar motion, held at this value)")
      ->capture_default_str();
  app->add_option("--ransac", flags->ransac, "RANSAC over motion pairs")
      ->check(CLI::IsMember({"on", "off"}))
      ->capture_default_str();
  app->add_option("--ransac_max_rotation_error_deg",
                  o.ransac_max_rotation_error_deg,
                  "inlier threshold on the rotation residual")
      ->capture_default_str();
  app->add_option("--ransac_max_translation_error_m",
                  o.ransac_max_translation_error_m,
                  "inlier threshold on the translation residual...")
      ->capture_default_str();
  app->add_option("--ransac_max_translation_error_rel",
                  o.ransac_max_translation_error_rel,
                  "...plus this fraction of the odometry step")
      ->capture_default_str();
  app->add_option("--ransac_min_inlier_ratio",
                  o.ransac_min_inlier_ratio,
                  "refuse the data below this inlier fraction")
      ->capture_default_str();
  app->add_option("--ransac_seed", o.ransac_seed, "RANSAC random seed")
      ->check(AtLeast(0))
      ->capture_default_str();
  app->add_option(
         "--robust_loss", flags->robust_loss, "robust loss of the refinement")
      ->check(CLI::IsMember({"none", "huber", "cauchy"}))
      ->capture_default_str();
  app->add_option("--robust_loss_scale",
                  o.robust_loss_scale,
                  "robust loss scale in standard deviations")
      ->capture_default_str();
  // Noise model (per keyframe pair).
  NoiseModel& n = o.noise;
  app->add_option("--odom_yaw_sigma_deg",
                  n.odom_yaw_sigma_deg,
                  "odometry yaw noise per pair")
      ->capture_default_str();
  app->add_option("--odom_yaw_sigma_rel",
                  n.odom_yaw_sigma_rel,
                  "+ this fraction of the yaw increment")
      ->capture_default_str();
  app->add_option("--odom_tilt_sigma_deg",
                  n.odom_tilt_sigma_deg,
                  "odometry roll/pitch noise per pair")
      ->capture_default_str();
  app->add_option("--odom_translation_sigma_m",
                  n.odom_translation_sigma_m,
                  "odometry translation noise per axis and pair")
      ->capture_default_str();
  app->add_option("--odom_translation_sigma_rel",
                  n.odom_translation_sigma_rel,
                  "+ this fraction of the step length")
      ->capture_default_str();
  app->add_option("--cam_rotation_sigma_deg",
                  n.cam_rotation_sigma_deg,
                  "camera rotation noise per axis and pair")
      ->capture_default_str();
  app->add_option("--cam_translation_sigma_rel",
                  n.cam_translation_sigma_rel,
                  "camera translation noise, fraction of the step length")
      ->capture_default_str();
  // Refusal thresholds.
  app->add_option("--min_rotation_deg",
                  o.min_rotation_deg,
                  "a pair excites rotation above this yaw")
      ->capture_default_str();
  app->add_option("--max_rotation_stddev_deg",
                  o.max_rotation_stddev_deg,
                  "larger: rotation reported unobservable")
      ->capture_default_str();
  app->add_option("--max_translation_stddev_m",
                  o.max_translation_stddev_m,
                  "larger: x/y reported unobservable")
      ->capture_default_str();
  app->add_option("--max_scale_stddev_rel",
                  o.max_scale_stddev_rel,
                  "larger: scale reported unobservable")
      ->capture_default_str();
}

void FinishCalibrationFlags(const CalibrationFlags& flags,
                            CalibrateInputs* inputs) {
  CalibrationOptions& o = inputs->calibration;
  o.method = LinearMethodFromString(flags.method);
  o.alsp_projection = PlaneProjectionFromString(flags.alsp_projection);
  o.use_ransac = flags.ransac == "on";
  o.robust_loss = RobustLossFromString(flags.robust_loss);
  o.refine = !flags.no_refine;
  inputs->odometry_format = ParseOdometryFormat(flags.odometry_format);
  inputs->camera_time_unit = ParseTimeUnit(flags.camera_time_unit);
  inputs->odometry_time_unit = ParseTimeUnit(flags.odometry_time_unit);
  inputs->odometry_time_unit_given = flags.odometry_time_unit_given;
  if (!std::isfinite(flags.camera_time_offset_s) ||
      std::abs(flags.camera_time_offset_s) > 1e9) {
    throw std::invalid_argument(
        "--camera_time_offset_s must be finite and within [-1e9, 1e9], got " +
        FormatNumber(flags.camera_time_offset_s));
  }
  inputs->association.camera_time_offset_ns =
      std::llround(flags.camera_time_offset_s * 1e9);
}

}  // namespace odomcal
