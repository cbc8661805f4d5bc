#include "odomcal/plugin/cli/rig_report.h"

#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/report/calibration_report.h"
#include "odomcal/plugin/report/joint_adjustment_report.h"
#include "odomcal/plugin/report/robot_outputs.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

namespace odomcal {
namespace {

using nlohmann::json;

// printf into a string, for lines with several numbers.
template <typename... Args>
std::string Printf(const char* format, Args... args) {
  char buffer[512];
  std::snprintf(buffer, sizeof(buffer), format, args...);
  return buffer;
}

json Vector3ToJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

json CameraToJson(const RigCameraRun& camera,
                  const RobotFrameNames& robot_frames) {
  const json full = CalibrationToJson(camera.run.result, camera.run.context);
  json out = {
      {"name", camera.name},
      {"status", camera.Status()},
      {"reason", camera.Reason()},
      {"calibrated", camera.Calibrated()},
      {"camera_poses", camera.run.context.camera_paths},
      {"camera_frame", RigCameraFrames(robot_frames, camera.name).camera_frame},
  };
  for (const char* key : {"odom_from_cam",
                          "cam_from_odom",
                          "metric_scales",
                          "metric_scale",
                          "unobservable",
                          "stddev",
                          "covariance",
                          "translation_z_source",
                          "camera_time_offset_s",
                          "warnings"}) {
    out[key] = full.contains(key) ? full[key] : json(nullptr);
  }
  const AssociationResult& a = camera.run.context.association;
  out["num_camera_poses"] = a.num_camera_poses;
  out["num_motion_pairs"] = camera.run.result.diagnostics.num_pairs_in;
  out["num_pairs_used"] = camera.run.result.diagnostics.num_pairs_used;
  out["time_offset"] = full.contains("diagnostics") &&
                               full["diagnostics"].contains("time_offset")
                           ? full["diagnostics"]["time_offset"]
                           : json(nullptr);
  return out;
}

json PairToJson(const RigCalibrationRun& rig, const RigCameraPair& pair) {
  const CameraPairTransform& t = pair.transform;
  json rows = json::array();
  for (int r = 0; r < 6; ++r) {
    json row = json::array();
    for (int c = 0; c < 6; ++c) row.push_back(t.covariance(r, c));
    rows.push_back(row);
  }
  json offset = Vector3ToJson(t.odom_offset_m);
  json offset_stddev = Vector3ToJson(t.stddev_odom_offset_m);
  if (t.odom_offset_z_held) offset_stddev[2] = nullptr;
  return {
      {"camera_a", rig.cameras[pair.camera_a].name},
      {"camera_b", rig.cameras[pair.camera_b].name},
      {"camb_from_cama",
       TransformToJson(t.camb_from_cama, true, true, true, true)},
      {"angle_deg", t.angle_deg},
      {"stddev",
       {{"roll_deg", t.stddev_roll_pitch_yaw_deg.x()},
        {"pitch_deg", t.stddev_roll_pitch_yaw_deg.y()},
        {"yaw_deg", t.stddev_roll_pitch_yaw_deg.z()},
        {"rotation_axes_deg", Vector3ToJson(t.stddev_rotation_axes_deg)},
        {"translation_m", Vector3ToJson(t.stddev_translation_m)}}},
      {"covariance",
       {{"order", {"rx", "ry", "rz", "tx", "ty", "tz"}},
        {"perturbation",
         std::string("rotation: left, R = Exp(psi) * R_hat, psi in radians "
                     "about camB's axes; translation: additive, metres, in "
                     "camB's frame; ") +
             (pair.adjusted_together
                  ? "from the rig's joint adjustment, with the two "
                    "cameras' cross terms"
                  : "from the two cameras' covariances as independent "
                    "estimates (no cross terms)")},
        {"matrix", rows}}},
      {"odom_offset_m", offset},
      {"stddev_odom_offset_m", offset_stddev},
      {"odom_offset_z_held", t.odom_offset_z_held},
      {"adjusted_together", pair.adjusted_together},
  };
}

// The rig's joint adjustment (`--joint_adjustment check` or `on`); null
// when it was not asked for (`off`, or a rig from `odomcal calibrate`).
json RigJointToJson(const RigCalibrationRun& rig) {
  const RigJointAdjustment& joint = rig.joint;
  if (!joint.ran && joint.skipped.empty()) return nullptr;
  json cameras = json::array();
  for (const int camera : joint.cameras) {
    cameras.push_back(rig.cameras.at(camera).name);
  }
  const auto measured = [](double sigmas) {
    return sigmas >= 0.0 ? json(sigmas) : json(nullptr);
  };
  json out = {
      {"use", ToString(joint.use)},
      {"ran", joint.ran},
      {"adopted", joint.Adopted()},
      {"max_disagreement_sigmas", measured(joint.max_disagreement_sigmas)},
      {"max_disagreement_sigmas_jackknifed",
       measured(joint.max_disagreement_sigmas_jackknifed)},
      {"status",
       joint.ran ? json(ToString(joint.result.status)) : json(nullptr)},
      {"message", joint.ran ? joint.result.message : joint.skipped},
      {"cameras", cameras},
      {"num_images", joint.num_images},
      {"num_points", joint.num_points},
      {"num_points_across_cameras", joint.num_points_across_cameras},
      {"num_links", joint.num_links},
      {"num_links_across_cameras", joint.num_links_across_cameras},
      {"num_clock_offsets_propagated", joint.num_clock_offsets_propagated},
      {"pixel_sigma", nullptr},
      {"odometry_sigma_ratio", nullptr},
      {"jackknife_blocks", nullptr}};
  if (joint.Succeeded()) {
    out["pixel_sigma"] = joint.result.pixel_sigma;
    out["odometry_sigma_ratio"] = joint.result.odometry_sigma_ratio;
    out["robot_poses"] = ToString(joint.result.motion_model);
    out["max_robot_tilt_deg"] = joint.result.max_robot_tilt_deg;
    out["ground_tilt_rate_deg_per_m"] =
        joint.result.motion_model == RobotMotionModel::kOnGround
            ? json(joint.result.ground_tilt_rate_deg_per_m)
            : json(nullptr);
    out["jackknife_blocks"] =
        joint.jackknife.ran ? json(joint.jackknife.num_blocks) : json(nullptr);
    out["camera_intrinsics"] = JointCameraIntrinsicsToJson(
        joint.cameras_before, joint.refine_intrinsics, joint.result.cameras);
    for (size_t c = 0; c < out["camera_intrinsics"].size(); ++c) {
      const int mount = joint.mount_of_camera.at(c);
      out["camera_intrinsics"][c]["camera"] =
          rig.cameras.at(joint.cameras.at(mount)).name;
    }
  }
  return out;
}

}  // namespace

CalibrationRun ReferenceRun(const RigCalibrationRun& rig) {
  CalibrationRun run = rig.cameras[rig.reference].run;
  for (const std::string& warning : rig.Warnings()) {
    run.result.warnings.push_back(warning);
  }
  return run;
}

RobotFrameNames RigCameraFrames(const RobotFrameNames& frames,
                                const std::string& name) {
  RobotFrameNames out = frames;
  out.camera_frame = name + "_" + frames.camera_frame;
  if (!frames.camera_body_frame.empty()) {
    out.camera_body_frame = name + "_" + frames.camera_body_frame;
  }
  return out;
}

std::optional<RobotDescription> RigRobotDescription(
    const RigCalibrationRun& rig) {
  std::optional<RobotDescription> merged;
  std::vector<FrameTransform> from_base, further;
  for (size_t k = 0; k < rig.cameras.size(); ++k) {
    const RigCameraRun& camera = rig.cameras[k];
    ReportContext context = camera.run.context;
    context.robot_frames =
        RigCameraFrames(camera.run.context.robot_frames, camera.name);
    // Wheel corrections are the reference camera's.
    if (static_cast<int>(k) != rig.reference) context.systematics.reset();
    const auto robot = RobotDescriptionOf(camera.run.result, context);
    if (!robot) continue;
    if (!merged) {
      merged = *robot;
      merged->frames = camera.run.context.robot_frames;
      merged->diff_drive.reset();
      merged->height_held = false;
    }
    merged->height_held = merged->height_held || robot->height_held;
    merged->held_height_m = robot->held_height_m;
    if (robot->diff_drive) merged->diff_drive = robot->diff_drive;
    // Transforms from the base frame first: Autoware's YAML groups the
    // children of each parent once.
    for (const FrameTransform& transform : robot->transforms) {
      (transform.parent == merged->frames.base_frame ? from_base : further)
          .push_back(transform);
    }
  }
  if (merged) {
    merged->transforms = from_base;
    merged->transforms.insert(
        merged->transforms.end(), further.begin(), further.end());
  }
  return merged;
}

json RigCalibrationToJson(const RigCalibrationRun& rig) {
  const CalibrationRun reference = ReferenceRun(rig);
  json out = CalibrationToJson(reference.result, reference.context);
  AddRigToJson(rig, &out);
  return out;
}

void AddRigToJson(const RigCalibrationRun& rig, json* result) {
  json& out = *result;
  const RobotFrameNames& frames =
      rig.cameras[rig.reference].run.context.robot_frames;
  out["robot"] = RobotToJson(RigRobotDescription(rig));
  out["reference_camera"] = rig.cameras[rig.reference].name;
  json cameras = json::array();
  json input_cameras = json::array();
  for (const RigCameraRun& camera : rig.cameras) {
    cameras.push_back(CameraToJson(camera, frames));
    input_cameras.push_back(
        {{"name", camera.name},
         {"camera_poses", camera.run.context.camera_paths}});
  }
  out["cameras"] = cameras;
  json pairs = json::array();
  for (const RigCameraPair& pair : rig.pairs) {
    pairs.push_back(PairToJson(rig, pair));
  }
  out["camera_pairs"] = pairs;
  out["rig_joint_adjustment"] = RigJointToJson(rig);
  out["inputs"]["cameras"] = input_cameras;
  out["inputs"]["reference_camera"] = rig.cameras[rig.reference].name;
}

std::string RigCalibrationSummary(const RigCalibrationRun& rig) {
  std::ostringstream out;
  const CalibrationRun reference = ReferenceRun(rig);
  out << "reference camera " << rig.cameras[rig.reference].name << ":\n";
  // The reference camera's summary without its robot lines (the rig's
  // follow).
  ReportContext context = reference.context;
  context.robot_frames =
      RigCameraFrames(context.robot_frames, rig.cameras[rig.reference].name);
  out << CalibrationSummary(reference.result, context);
  out << "  cameras (" << rig.NumCalibrated() << " of " << rig.cameras.size()
      << " calibrated):\n";
  for (const RigCameraRun& camera : rig.cameras) {
    out << "    " << camera.name << ": " << camera.Status();
    if (camera.Calibrated()) {
      const CalibrationResult& r = camera.run.result;
      const Eigen::Vector3d rpy =
          RollPitchYaw(r.odom_from_cam.rotation) * kRadToDeg;
      const Eigen::Vector3d& t = r.odom_from_cam.translation;
      out << Printf(
          "; roll pitch yaw %.3f %.3f %.3f deg (3 sigma %.3f %.3f %.3f); "
          "x y %.2f %.2f cm (3 sigma %.2f %.2f), z %.2f cm",
          rpy.x(),
          rpy.y(),
          rpy.z(),
          3.0 * r.stddev_roll_pitch_yaw_deg.x(),
          3.0 * r.stddev_roll_pitch_yaw_deg.y(),
          3.0 * r.stddev_roll_pitch_yaw_deg.z(),
          100.0 * t.x(),
          100.0 * t.y(),
          300.0 * r.stddev_translation_xy_m.x(),
          300.0 * r.stddev_translation_xy_m.y(),
          100.0 * t.z());
      if (camera.run.context.systematics) {
        out << Printf(
            "; clock offset %.4f s",
            NsToSeconds(camera.run.context.systematics->camera_time_offset_ns));
      }
    } else {
      out << ": " << camera.Reason();
    }
    out << "\n";
  }
  if (rig.joint.Succeeded() && !rig.joint.Adopted()) {
    out << "  rig joint adjustment check: every camera's own estimate "
           "stands (the cameras adjusted together differ from them by at "
           "most "
        << Printf("%.1f", rig.joint.FinalDisagreementSigmas())
        << " sigma of the difference)\n";
  }
  if (rig.joint.Adopted()) {
    std::string names;
    for (const int camera : rig.joint.cameras) {
      names += (names.empty() ? "" : ", ") + rig.cameras.at(camera).name;
    }
    out << "  rig joint adjustment: " << names << " adjusted together ("
        << rig.joint.num_images << " images, " << rig.joint.num_points
        << " points (" << rig.joint.num_points_across_cameras
        << " seen by several cameras), " << rig.joint.num_links
        << " odometry links, " << rig.joint.num_links_across_cameras
        << Printf(" across cameras; reprojection rms %.2f px",
                  rig.joint.result.reprojection_rms_px_after)
        << "): their rotation and x/y are its, and the transforms between "
           "them carry its cross terms\n";
  }
  for (const RigCameraPair& pair : rig.pairs) {
    const CameraPairTransform& t = pair.transform;
    const Eigen::Vector3d rpy =
        RollPitchYaw(t.camb_from_cama.rotation) * kRadToDeg;
    const Eigen::Vector3d& x = t.camb_from_cama.translation;
    out << "  " << rig.cameras[pair.camera_b].name << "_from_"
        << rig.cameras[pair.camera_a].name
        << Printf(
               ": roll pitch yaw %.3f %.3f %.3f deg (3 sigma about camB's "
               "x y z %.3f %.3f %.3f deg); translation %.2f %.2f %.2f cm "
               "(3 sigma %.2f %.2f %.2f)%s\n",
               rpy.x(),
               rpy.y(),
               rpy.z(),
               3.0 * t.stddev_rotation_axes_deg.x(),
               3.0 * t.stddev_rotation_axes_deg.y(),
               3.0 * t.stddev_rotation_axes_deg.z(),
               100.0 * x.x(),
               100.0 * x.y(),
               100.0 * x.z(),
               300.0 * t.stddev_translation_m.x(),
               300.0 * t.stddev_translation_m.y(),
               300.0 * t.stddev_translation_m.z(),
               t.odom_offset_z_held ? "; the heights' difference is held" : "");
  }
  if (const auto robot = RigRobotDescription(rig)) {
    out << "  robot outputs:";
    const char* separator = " ";
    for (const FrameTransform& transform : robot->transforms) {
      out << separator << transform.parent << " -> " << transform.child;
      separator = ", ";
    }
    out << "\n";
  }
  return out.str();
}

void WriteRigCalibrationOutputs(const RigCalibrationRun& rig,
                                const std::string& json_path,
                                bool overwrite) {
  const std::string yaml_path = ReplaceExtension(json_path, ".yaml");
  CheckOutputPath(json_path, overwrite);
  CheckOutputPath(yaml_path, overwrite);
  WriteFileAtomically(json_path, RigCalibrationToJson(rig).dump(2) + "\n");
  WriteFileAtomically(yaml_path,
                      CalibrationToYaml(rig.cameras[rig.reference].run.result));
  WriteRobotOutputsBeside(json_path, RigRobotDescription(rig), overwrite);
}

int RigExitCode(const RigCalibrationRun& rig) {
  return rig.NumCalibrated() > 0 ? kExitSuccess : kExitNotCalibrated;
}

}  // namespace odomcal
