#include "odomcal/plugin/cli/colmap_rig_outputs.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/plugin/cli/rig_report.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/colmap_calibration_outputs.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/plugin/report/rig_report_html.h"
#include "odomcal/solver/format_number.h"

#include <filesystem>

namespace odomcal {
namespace {

using nlohmann::json;

// What only a COLMAP project's cameras have: their COLMAP cameras, image
// counts and folders, and the scales two cameras found for one sub-model.
void AddColmapRigToJson(const ColmapRigRun& rig, json* result) {
  json& out = *result;
  out["camera_grouping"] = ColmapCameraGroupingText(rig.grouping);
  for (size_t k = 0; k < rig.cameras.size(); ++k) {
    const ColmapRigCameraRun& camera = rig.cameras[k];
    json& entry = out["cameras"][k];
    entry["colmap_camera_ids"] = camera.camera.camera_ids;
    entry["num_registered_images"] = camera.camera.num_images;
    entry["outputs"] = camera.run ? json("cameras/" + camera.camera.name + "/")
                                  : json(nullptr);
    out["inputs"]["cameras"][k]["colmap_camera_ids"] = camera.camera.camera_ids;
  }
  json shared = json::array();
  for (const SharedSubModelScale& scale : rig.shared_scales) {
    shared.push_back({{"camera_a", rig.cameras[scale.camera_a].camera.name},
                      {"camera_b", rig.cameras[scale.camera_b].camera.name},
                      {"sub_model", scale.sub_model},
                      {"metric_scale_a", scale.scale_a},
                      {"metric_scale_b", scale.scale_b},
                      {"difference_sigmas", scale.sigmas},
                      {"disagree", scale.Disagrees()}});
  }
  out["shared_scales"] = shared;
}

// The rig's section of report.html from the two views of the rig.
RigReport ColmapRigReport(const ColmapRigRun& rig,
                          const RigCalibrationRun& as_rig) {
  RigReport report;
  report.reference = as_rig.reference;
  for (size_t k = 0; k < as_rig.cameras.size(); ++k) {
    const RigCameraRun& camera = as_rig.cameras[k];
    RigReportCamera& out = report.cameras.emplace_back();
    out.name = camera.name;
    out.status = camera.Status();
    out.reason = camera.Reason();
    out.calibrated = camera.Calibrated();
    out.result = camera.run.result;
    if (const auto& systematics = camera.run.context.systematics) {
      out.clock_offset_s = NsToSeconds(systematics->camera_time_offset_ns);
      out.clock_offset_estimated = systematics->time_offset_estimated;
      out.clock_offset_stddev_s = systematics->camera_time_offset_stddev_s;
    }
    out.num_images = rig.cameras[k].camera.num_images;
    if (rig.cameras[k].run) {
      out.report_path = "cameras/" + camera.name + "/report.html";
    }
  }
  for (const RigCameraPair& pair : as_rig.pairs) {
    report.pairs.push_back(
        {pair.camera_a, pair.camera_b, pair.transform, pair.adjusted_together});
  }
  report.shared_scales = rig.shared_scales;
  if (as_rig.joint.Adopted()) {
    for (const int camera : as_rig.joint.cameras) {
      report.adjusted_together.push_back(as_rig.cameras.at(camera).name);
    }
    report.num_points_across_cameras = as_rig.joint.num_points_across_cameras;
    report.joint_note =
        as_rig.joint.use == JointAdjustmentUse::kOn
            ? "--joint_adjustment on"
            : "reported because the images of all cameras contradicted the "
              "cameras' own estimates, see the warnings";
  } else if (as_rig.joint.Succeeded()) {
    report.joint_note =
        "The cameras adjusted together with the odometry (the default "
        "check, --joint_adjustment check) agree with each camera's own "
        "estimate within " +
        FormatPrintf("%.1f", as_rig.joint.FinalDisagreementSigmas()) +
        " sigma of the difference: each camera's own estimate stands.";
  }
  return report;
}

}  // namespace

RigCalibrationRun RigCalibrationOf(const ColmapRigRun& rig,
                                   const std::string& command,
                                   const nlohmann::json& flag_echo) {
  RigCalibrationRun out;
  out.reference = rig.reference;
  for (const ColmapRigCameraRun& camera : rig.cameras) {
    RigCameraRun camera_run;
    camera_run.name = camera.camera.name;
    if (camera.run) {
      camera_run.run.result = camera.run->check.result;
      camera_run.run.context =
          ProjectReportContext(camera.inputs, *camera.run, command, flag_echo);
    } else {
      camera_run.input_error = camera.input_error;
      camera_run.failure_status = camera.failure_status;
      camera_run.run.result.message = camera.input_error;
      camera_run.run.context.command = command;
      camera_run.run.context.camera_paths = {camera.inputs.model_path};
      camera_run.run.context.odometry_path = camera.inputs.odometry_path;
      camera_run.run.context.robot_frames = camera.inputs.robot_frames;
      camera_run.run.context.flag_echo = flag_echo;
    }
    camera_run.extrinsic = ExtrinsicOf(camera_run.run.result);
    out.cameras.push_back(std::move(camera_run));
  }
  out.findings = SharedScaleWarnings(rig);
  // Every camera has the project's options (and its own camera ids).
  AdoptRigJointAdjustment(
      rig.joint, rig.cameras.at(rig.reference).inputs.calibration, &out);
  return out;
}

namespace {

// The reference camera's run with the rig's warnings, and its context; an
// empty run when its images did not fit the odometry (no model, no report
// of its own).
std::pair<ColmapCalibrationRun, ReportContext> ReferenceColmapRun(
    const ColmapRigRun& rig, const RigCalibrationRun& as_rig) {
  const ColmapRigCameraRun& reference = rig.cameras.at(rig.reference);
  ColmapCalibrationRun run =
      reference.run ? *reference.run : ColmapCalibrationRun();
  CalibrationRun result = ReferenceRun(as_rig);
  run.check.result = std::move(result.result);
  return {std::move(run), std::move(result.context)};
}

json RigJsonOf(const ColmapRigRun& rig,
               const RigCalibrationRun& as_rig,
               const ColmapCalibrationRun& reference_run,
               const ReportContext& context) {
  json out = ColmapCalibrationToJson(reference_run, context);
  AddRigToJson(as_rig, &out);
  AddColmapRigToJson(rig, &out);
  return out;
}

}  // namespace

nlohmann::json ColmapRigToJson(const ColmapRigRun& rig,
                               const RigCalibrationRun& as_rig) {
  const auto [reference_run, context] = ReferenceColmapRun(rig, as_rig);
  return RigJsonOf(rig, as_rig, reference_run, context);
}

std::vector<std::string> WriteColmapRigOutputs(const ColmapRigRun& rig,
                                               const RigCalibrationRun& as_rig,
                                               const std::string& output_dir,
                                               bool write_camera_folders) {
  namespace fs = std::filesystem;
  const auto [reference_run, context] = ReferenceColmapRun(rig, as_rig);
  RigOverrides overrides;
  // The reference run copied once, for the JSON and the files.
  overrides.result = RigJsonOf(rig, as_rig, reference_run, context);
  overrides.robot = RigRobotDescription(as_rig);
  overrides.report_section = RigReportHtml(ColmapRigReport(rig, as_rig));
  std::vector<std::string> written = WriteColmapCalibrationOutputs(
      reference_run, context, output_dir, &overrides);

  // cameras/<name>/: each camera's own files; an earlier run's go first.
  if (write_camera_folders) RemoveOwnedOutput(output_dir, "cameras");
  for (size_t k = 0; k < rig.cameras.size(); ++k) {
    const ColmapRigCameraRun& camera = rig.cameras[k];
    if (!camera.run) continue;
    if (!write_camera_folders) {
      written.push_back("cameras/" + camera.camera.name + "/");
      continue;
    }
    const std::string folder =
        (fs::path(output_dir) / "cameras" / camera.camera.name).string();
    ClaimOutputFolder(
        folder, ColmapCalibrationOutputEntries(), ExistingOutputs::kReplaceOwn);
    WriteColmapCalibrationOutputs(
        *camera.run, as_rig.cameras[k].run.context, folder);
    written.push_back("cameras/" + camera.camera.name + "/");
  }
  return written;
}

}  // namespace odomcal
