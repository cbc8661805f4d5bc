#include "odomcal/plugin/options/project_flags.h"

#include "odomcal/adapters/timestamp.h"

#include <cstdlib>
#include <string>

namespace odomcal {
namespace {

using Project = ColmapCalibrationInputs;

// A path flag: no default, checked to exist (`check`); echoed as given,
// null when not given.
OptionRow<Project> PathRow(std::string name,
                           std::string help,
                           std::string Project::*field,
                           bool required,
                           FlagCheck check) {
  OptionRow<Project> row;
  row.name = name;
  row.help = std::move(help);
  row.echo_key = std::move(name);
  row.value = OptionField<Project, std::string>(
      [field](Project& inputs) -> std::string& { return inputs.*field; });
  row.check = std::move(check);
  row.required = required;
  row.show_default = false;
  row.echo = [field](const Project& inputs) {
    const std::string& path = inputs.*field;
    return path.empty() ? nlohmann::json(nullptr) : nlohmann::json(path);
  };
  return row;
}

}  // namespace

const OptionTable<ColmapCalibrationInputs>& ColmapModelFlags() {
  static const OptionTable<Project> table = {
      PathRow("model_path",
              "COLMAP sparse model folder, or the mapper's output folder with "
              "sub-models 0, 1, ...",
              &Project::model_path,
              true,
              FlagCheck::ExistingDirectory()),
      PathRow("database_path",
              "the project's database.db (read-only; counts unregistered "
              "images)",
              &Project::database_path,
              false,
              FlagCheck::ExistingFile()),
  };
  return table;
}

const OptionTable<ColmapCalibrationInputs>& ProjectInputFlags() {
  static const OptionTable<Project> table = {
      PathRow("odometry",
              "wheel odometry: CSV 'timestamp,x,y,yaw' (m, rad) or TUM "
              "origin_from_odom",
              &Project::odometry_path,
              true,
              FlagCheck::ExistingFile()),
      PathRow("image_timestamps",
              "CSV 'image_name,timestamp' (unit: --camera_time_unit); "
              "without it, times come from numeric image file names",
              &Project::image_timestamps_path,
              false,
              FlagCheck::ExistingFile()),
      ChoiceRow<Project>(
          "file_name_time_unit",
          "unit of numeric image file names; auto: integer stems are ns, "
          "stems with a decimal point are s",
          {"auto", "s", "ms", "us", "ns"},
          [](const Project& inputs) -> std::string {
            return inputs.file_name_time_unit
                       ? TimeUnitName(*inputs.file_name_time_unit)
                       : "auto";
          },
          [](Project* inputs, const std::string& name) {
            inputs->file_name_time_unit.reset();
            if (name != "auto")
              inputs->file_name_time_unit = ParseTimeUnit(name);
          }),
  };
  return table;
}

const OptionTable<StretchOptions>& StretchFlags() {
  static const OptionTable<StretchOptions> table = {
      NumberRow<StretchOptions>(
          "min_inconsistent_run_pairs",
          "motion pairs contradicting the odometry (outside RANSAC's gate "
          "under the fit) within a run of consecutive unused pairs that make "
          "the run a stretch to cut out or split off",
          [](auto& o) -> auto& { return o.min_run_pairs; },
          FlagCheck::AtLeast(1)),
  };
  return table;
}

const OptionTable<FloorPlaneOptions>& FloorPlaneFlags() {
  using F = FloorPlaneOptions;
  static const OptionTable<F> table = {
      ChoiceRow<F>(
          "floor_plane",
          "translation z from the floor under the metric model: estimate "
          "(held with the reason where the floor is not seen well enough), "
          "check (fit and cross-check only; the default when "
          "--fixed_translation_z_m is given) or off",
          {"estimate", "check", "off"},
          [](const F& o) { return ToString(o.use); },
          [](F* o, const std::string& name) {
            o->use = FloorPlaneUseFromString(name);
          }),
      NumberRow<F>(
          "odometry_height_m",
          "height of the odometry frame's origin above the floor (0: REP "
          "120 base_footprint); z = camera height - this",
          [](auto& o) -> auto& { return o.odometry_height_m; }),
      NumberRow<F>(
          "floor_max_path_distance_m",
          "floor points: at most this far (horizontally) from a camera",
          [](auto& o) -> auto& { return o.max_path_distance_m; },
          FlagCheck::AtLeast(0.0)),
      NumberRow<F>(
          "floor_inlier_distance_m",
          "RANSAC inlier distance of the floor plane",
          [](auto& o) -> auto& { return o.ransac_inlier_distance_m; },
          FlagCheck::AtLeast(0.0)),
      NumberRow<F>(
          "floor_max_slope_deg",
          "a floor tilted more than this against the plane driven in "
          "(beyond 3 sigma) is sloped, and a floor whose tilt is too "
          "uncertain to tell this much is not used: z stays held",
          [](auto& o) -> auto& { return o.max_slope_deg; },
          FlagCheck::AtLeast(0.0)),
  };
  return table;
}

const OptionTable<JointAdjustmentSettings>& JointAdjustmentFlags() {
  using J = JointAdjustmentSettings;
  static const OptionTable<J> table = {
      ChoiceRow<J>(
          "joint_adjustment",
          "after the two-step calibration, one bundle adjustment of the "
          "images, the wheel odometry and the extrinsic in metres. on: its "
          "extrinsic and one metric model without COLMAP's scale drift are "
          "reported; check: it checks the two-step estimate, which is "
          "reported unless the adjustment contradicts it (more than 3 "
          "sigma apart), then the adjustment's is; off: not run",
          {"on", "off", "check"},
          [](const J& o) { return ToString(o.use); },
          [](J* o, const std::string& name) {
            o->use = JointAdjustmentUseFromString(name);
          }),
      ChoiceRow<J>(
          "joint_intrinsics",
          "the camera intrinsics in the joint adjustment: held as the model "
          "has them; refined (focal length and distortion, the principal "
          "point held); auto: refined where COLMAP's bundle adjustment "
          "changed them from the database's camera, else held",
          {"auto", "held", "refined"},
          [](const J& o) { return ToString(o.intrinsics); },
          [](J* o, const std::string& name) {
            o->intrinsics = JointIntrinsicsFromString(name);
          }),
      NumberRow<J>(
          "joint_max_reprojection_sigmas",
          "observations beyond this many pixel sigmas are left out of the "
          "joint adjustment",
          [](auto& o) -> auto& { return o.options.max_reprojection_sigmas; },
          FlagCheck::AtLeast(1.0)),
      NumberRow<J>(
          "joint_jackknife_blocks",
          "the joint adjustment solved again without each of this many "
          "stretches of the drive's images; their spread widens the stated "
          "sigma where the noise model understates it (0: off)",
          [](auto& o) -> auto& { return o.jackknife.num_blocks; },
          // 0 or at least 3 (JointJackknifeOptions::Check).
          FlagCheck::Custom([](const std::string& text) {
            char* end = nullptr;
            const long value = std::strtol(text.c_str(), &end, 10);
            // Not an integer: the integer flag's own error says so.
            if (end == text.c_str() || *end != '\0') return std::string();
            return value == 0 || value >= 3
                       ? std::string()
                       : "must be 0 (off) or >= 3, got " + text;
          })),
  };
  return table;
}

nlohmann::json ProjectFlagsEcho(const ColmapCalibrationInputs& inputs) {
  nlohmann::json echo = CalibrationFlagsEcho(inputs.association,
                                             inputs.calibration,
                                             inputs.systematics,
                                             inputs.robot_frames);
  EchoOptions(ColmapModelFlags(), inputs, &echo["inputs"]);
  EchoOptions(ProjectInputFlags(), inputs, &echo["inputs"]);
  EchoOptions(StretchFlags(), inputs.stretch, &echo["options"]);
  EchoOptions(FloorPlaneFlags(), inputs.floor, &echo["options"]);
  EchoOptions(
      JointAdjustmentFlags(), inputs.joint_adjustment, &echo["options"]);
  return echo;
}

}  // namespace odomcal
