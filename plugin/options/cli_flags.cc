#include "odomcal/plugin/options/cli_flags.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/format_number.h"

#include <cmath>
#include <cstdlib>
#include <string>
#include <utility>

namespace odomcal {
namespace {

using Association = AssociationOptions;
using Calibration = CalibrationOptions;

// The offset is stored in integer nanoseconds: it must fit with room.
std::string TimeOffsetError(const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) {
    return "must be a number, got '" + text + "'";
  }
  if (!std::isfinite(value) || std::abs(value) > 1e9) {
    return "must be finite and within [-1e9, 1e9], got " + FormatNumber(value);
  }
  return "";
}

OptionRow<Association> TimeOffsetRow() {
  OptionRow<Association> row;
  row.name = "camera_time_offset_s";
  row.echo_key = row.name;
  row.help = "added to camera times to get odometry times";
  // ns / 1e9: the double nearest the exact decimal (0.123456789 echoes as
  // given; 1e-9 * ns can end in ...00000001).
  const auto seconds = [](const Association& options) {
    return NsToSeconds(options.camera_time_offset_ns);
  };
  row.value = OptionText<Association>{
      {},
      [seconds](const Association& options) {
        return FormatNumber(seconds(options));
      },
      [](Association* options, const std::string& text) {
        options->camera_time_offset_ns =
            std::llround(std::strtod(text.c_str(), nullptr) * 1e9);
      },
      "FLOAT"};
  row.check = FlagCheck::Custom(TimeOffsetError);
  row.echo = [seconds](const Association& options) {
    return nlohmann::json(seconds(options));
  };
  return row;
}

// "auto" (the default: from the odometry's sampling, see
// AutomaticOdometryGapS) or seconds > 0, the form the flag always had. The
// report replaces "auto" by the value used (calibration_report.cc).
OptionRow<Association> OdometryGapRow() {
  return AutoOrNumberRow<Association>(
      "max_odometry_gap_s",
      "camera times in odometry gaps longer than this are skipped (auto: 2.5 "
      "odometry sample intervals, within [0.25, 1] s)",
      [](auto& o) -> auto& { return o.max_odometry_gap_s; },
      kAutomaticOdometryGap,
      AutoOrNumberLimit{0.0, false});
}

// A keyframe threshold: "auto" (the default: the camera poses choose the
// spacing, association.h) or a number >= 0. The help names both automatic
// values from association.h's spacings.
template <typename Field>
OptionRow<Association> KeyframeThresholdRow(std::string name,
                                            const std::string& help,
                                            double KeyframeSpacing::*spacing,
                                            Field field) {
  return AutoOrNumberRow<Association>(
      std::move(name),
      help + " (auto: " + FormatNumber(kDriftingPosesKeyframeSpacing.*spacing) +
          " for drifting camera poses, else " +
          FormatNumber(kConsistentPosesKeyframeSpacing.*spacing) + ")",
      field,
      kAutomaticKeyframeSpacing,
      AutoOrNumberLimit{0.0, true});
}

}  // namespace

const OptionTable<AssociationOptions>& AssociationFlags() {
  static const OptionTable<Association> table = {
      TimeOffsetRow(),
      OdometryGapRow(),
      KeyframeThresholdRow(
          "keyframe_min_rotation_deg",
          "next keyframe after this much odometry rotation...",
          &KeyframeSpacing::min_rotation_deg,
          [](auto& o) -> auto& { return o.keyframe_min_rotation_deg; }),
      KeyframeThresholdRow(
          "keyframe_min_translation_m",
          "...or this much odometry translation",
          &KeyframeSpacing::min_translation_m,
          [](auto& o) -> auto& { return o.keyframe_min_translation_m; }),
  };
  return table;
}

const OptionTable<CalibrationOptions>& CalibrationOptionFlags() {
  using C = Calibration;
  static const OptionTable<C> table = {
      // The estimator.
      ChoiceRow<C>(
          "method",
          "closed form",
          {"alsp", "als"},
          [](const C& o) { return ToString(o.method); },
          [](C* o, const std::string& name) {
            o->method = LinearMethodFromString(name);
          }),
      ChoiceRow<C>(
          "alsp_projection",
          "ALSP projection of camera translations onto the plane",
          {"orthogonal", "length_preserving"},
          [](const C& o) { return ToString(o.alsp_projection); },
          [](C* o, const std::string& name) {
            o->alsp_projection = PlaneProjectionFromString(name);
          }),
      SwitchRow<C>(
          "no_refine",
          "report the closed form without Ceres refinement",
          "refine",
          [](auto& o) -> auto& { return o.refine; },
          false),
      NumberRow<C>(
          "fixed_translation_z_m",
          "z of the camera in the odometry frame (unobservable under "
          "planar motion, held at this value)",
          [](auto& o) -> auto& { return o.fixed_translation_z_m; }),
      NumberRow<C>(
          "translation_z_prior_sigma_m",
          "standard deviation of the held z as a prior: where SE(3) odometry "
          "informs z without determining it, z is estimated under it and "
          "its uncertainty enters the covariance of x, y and the rotation "
          "(0: z held exactly)",
          [](auto& o) -> auto& { return o.translation_z_prior_sigma_m; }),
      // Outliers. --ransac on|off is echoed as the boolean "ransac".
      [] {
        OptionRow<C> row = ChoiceRow<C>(
            "ransac",
            "RANSAC over motion pairs",
            {"on", "off"},
            [](const C& o) { return std::string(o.use_ransac ? "on" : "off"); },
            [](C* o, const std::string& name) {
              o->use_ransac = name == "on";
            });
        row.echo = [](const C& o) { return nlohmann::json(o.use_ransac); };
        return row;
      }(),
      NumberRow<C>(
          "ransac_max_rotation_error_deg",
          "inlier threshold on the rotation residual",
          [](auto& o) -> auto& { return o.ransac_max_rotation_error_deg; }),
      NumberRow<C>(
          "ransac_max_translation_error_m",
          "inlier threshold on the translation residual...",
          [](auto& o) -> auto& { return o.ransac_max_translation_error_m; }),
      NumberRow<C>(
          "ransac_max_translation_error_rel",
          "...plus this fraction of the odometry step",
          [](auto& o) -> auto& { return o.ransac_max_translation_error_rel; }),
      NumberRow<C>(
          "ransac_min_inlier_ratio",
          "refuse the data below this inlier fraction",
          [](auto& o) -> auto& { return o.ransac_min_inlier_ratio; }),
      NumberRow<C>(
          "ransac_seed",
          "RANSAC random seed",
          [](auto& o) -> auto& { return o.ransac_seed; },
          FlagCheck::AtLeast(0)),
      ChoiceRow<C>(
          "robust_loss",
          "robust loss of the refinement",
          {"none", "huber", "cauchy"},
          [](const C& o) { return ToString(o.robust_loss); },
          [](C* o, const std::string& name) {
            o->robust_loss = RobustLossFromString(name);
          }),
      NumberRow<C>(
          "robust_loss_scale",
          "robust loss scale in standard deviations",
          [](auto& o) -> auto& { return o.robust_loss_scale; }),
      // Noise model (per keyframe pair).
      EchoedIn(
          "noise",
          NumberRow<C>(
              "odom_yaw_sigma_deg",
              "odometry yaw noise per pair",
              [](auto& o) -> auto& { return o.noise.odom_yaw_sigma_deg; })),
      EchoedIn(
          "noise",
          NumberRow<C>(
              "odom_yaw_sigma_rel",
              "+ this fraction of the yaw increment",
              [](auto& o) -> auto& { return o.noise.odom_yaw_sigma_rel; })),
      EchoedIn(
          "noise",
          NumberRow<C>(
              "odom_tilt_sigma_deg",
              "odometry roll/pitch noise per pair (a planar log: also its "
              "height noise, this slope over the step)",
              [](auto& o) -> auto& { return o.noise.odom_tilt_sigma_deg; })),
      EchoedIn("noise",
               NumberRow<C>(
                   "odom_translation_sigma_m",
                   "odometry translation noise per axis and pair (a planar "
                   "log's height: only this constant part)",
                   [](auto& o) -> auto& {
                     return o.noise.odom_translation_sigma_m;
                   })),
      EchoedIn("noise",
               NumberRow<C>(
                   "odom_translation_sigma_rel",
                   "+ this fraction of the step length",
                   [](auto& o) -> auto& {
                     return o.noise.odom_translation_sigma_rel;
                   })),
      EchoedIn(
          "noise",
          NumberRow<C>(
              "cam_rotation_sigma_deg",
              "camera rotation noise per axis and pair",
              [](auto& o) -> auto& { return o.noise.cam_rotation_sigma_deg; })),
      EchoedIn("noise",
               NumberRow<C>(
                   "cam_translation_sigma_rel",
                   "camera translation noise, fraction of the step length",
                   [](auto& o) -> auto& {
                     return o.noise.cam_translation_sigma_rel;
                   })),
      // Refusal thresholds.
      NumberRow<C>(
          "min_rotation_deg",
          "a pair excites rotation above this yaw",
          [](auto& o) -> auto& { return o.min_rotation_deg; }),
      NumberRow<C>(
          "max_rotation_stddev_deg",
          "larger: rotation reported unobservable",
          [](auto& o) -> auto& { return o.max_rotation_stddev_deg; }),
      NumberRow<C>(
          "max_translation_stddev_m",
          "larger: x/y reported unobservable",
          [](auto& o) -> auto& { return o.max_translation_stddev_m; }),
      NumberRow<C>(
          "max_scale_stddev_rel",
          "larger: scale reported unobservable",
          [](auto& o) -> auto& { return o.max_scale_stddev_rel; }),
      // Noise estimated from the data; echoed as the boolean
      // "estimate_noise".
      [] {
        OptionRow<C> row = ChoiceRow<C>(
            "estimate_noise",
            "estimate the noise levels from the data (the noise flags are "
            "the starting point)",
            {"on", "off"},
            [](const C& o) {
              return std::string(o.estimate_noise ? "on" : "off");
            },
            [](C* o, const std::string& name) {
              o->estimate_noise = name == "on";
            });
        row.echo = [](const C& o) { return nlohmann::json(o.estimate_noise); };
        return row;
      }(),
      NumberRow<C>(
          "noise_prior_weight",
          "weight of the noise flags in the noise estimation, in "
          "pseudo-observations per noise level (0: the data alone)",
          [](auto& o) -> auto& { return o.noise_prior_weight; }),
  };
  return table;
}

const OptionTable<SystematicsEstimationOptions>& SystematicsFlags() {
  using S = SystematicsEstimationOptions;
  const auto on_off = [](const char* name, const char* help, bool S::*field) {
    OptionRow<S> row = ChoiceRow<S>(
        name,
        help,
        {"on", "off"},
        [field](const S& o) { return std::string(o.*field ? "on" : "off"); },
        [field](S* o, const std::string& value) { o->*field = value == "on"; });
    row.echo = [field](const S& o) { return nlohmann::json(o.*field); };
    return row;
  };
  static const OptionTable<S> table = {
      on_off("estimate_time_offset",
             "estimate the clock offset (--camera_time_offset_s is the start)",
             &S::estimate_time_offset),
      NumberRow<S>(
          "time_offset_search_s",
          "coarse offset search over +- this around --camera_time_offset_s",
          [](auto& o) -> auto& { return o.time_offset_search_s; },
          FlagCheck::InRange(0.001, 3600)),
      on_off("estimate_odometry_intrinsics",
             "estimate yaw scale, yaw per metre and yaw-rate bias of the "
             "odometry",
             &S::estimate_odometry_intrinsics),
      NumberRow<S>(
          "wheel_track_m",
          "nominal wheel track: report the right/left wheel radius ratio "
          "(0: not given)",
          [](auto& o) -> auto& { return o.wheel_track_m; },
          FlagCheck::AtLeast(0)),
      NumberRow<S>(
          "wheel_ticks_per_m",
          "encoder ticks per metre of wheel travel, for an odometry CSV "
          "timestamp,left_ticks,right_ticks (0: not given)",
          [](auto& o) -> auto& { return o.wheel_ticks_per_m; },
          FlagCheck::AtLeast(0)),
  };
  return table;
}

const OptionTable<RobotFrameNames>& RobotFrameFlags() {
  static const OptionTable<RobotFrameNames> table = {
      NumberRow<RobotFrameNames>(
          "base_frame",
          "the robot's base frame, the camera's parent in the URDF, tf and "
          "Autoware outputs",
          [](auto& o) -> auto& { return o.base_frame; }),
      NumberRow<RobotFrameNames>(
          "camera_frame",
          "the camera's optical frame (x right, y down, z forward) in those "
          "outputs",
          [](auto& o) -> auto& { return o.camera_frame; }),
      NumberRow<RobotFrameNames>(
          "camera_body_frame",
          "the camera's REP 103 body frame (x forward, y left, z up) between "
          "the two, e.g. camera_link (empty: none)",
          [](auto& o) -> auto& { return o.camera_body_frame; }),
  };
  return table;
}

nlohmann::json CalibrationFlagsEcho(
    const AssociationOptions& association,
    const CalibrationOptions& calibration,
    const SystematicsEstimationOptions& systematics,
    const RobotFrameNames& robot_frames) {
  nlohmann::json echo = {{"inputs", nlohmann::json::object()},
                         {"options", nlohmann::json::object()}};
  EchoOptions(AssociationFlags(), association, &echo["inputs"]);
  EchoOptions(CalibrationOptionFlags(), calibration, &echo["options"]);
  EchoOptions(SystematicsFlags(), systematics, &echo["options"]);
  EchoOptions(RobotFrameFlags(), robot_frames, &echo["options"]);
  return echo;
}

}  // namespace odomcal
