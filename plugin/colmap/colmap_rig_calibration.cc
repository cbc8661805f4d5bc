#include "odomcal/plugin/colmap/colmap_rig_calibration.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/solver/format_number.h"

#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

namespace odomcal {
namespace {

// The scale of each sub-model calibrated as one segment (not cut into parts
// with scales of their own), with its relative sigma (0 when not given).
std::map<std::string, std::pair<double, double>> WholeSubModelScales(
    const ColmapCalibrationRun& run) {
  const CalibrationResult& result = run.check.result;
  const std::vector<int>& input_of = run.check.input_segment_of_output_segment;
  std::map<int, int> parts;
  for (const int input : input_of) ++parts[input];
  std::map<std::string, std::pair<double, double>> scales;
  for (size_t output = 0;
       output < input_of.size() && output < result.metric_scales.size();
       ++output) {
    const int input = input_of[output];
    const double scale = result.metric_scales[output];
    if (parts[input] != 1 || !(scale > 0.0)) continue;
    const double relative = output < result.stddev_metric_scales_rel.size()
                                ? result.stddev_metric_scales_rel[output]
                                : 0.0;
    scales[run.segments.at(input).sub_model] = {scale, relative};
  }
  return scales;
}

}  // namespace

bool SharedSubModelScale::Disagrees() const { return std::abs(sigmas) > 3.0; }

int ColmapReferenceCamera(const ColmapProjectCameras& cameras,
                          const std::string& name) {
  if (name.empty()) return 0;
  std::string names;
  for (size_t k = 0; k < cameras.cameras.size(); ++k) {
    if (cameras.cameras[k].name == name) return static_cast<int>(k);
    names += (names.empty() ? "" : ", ") + cameras.cameras[k].name;
  }
  throw std::invalid_argument("--reference_camera '" + name +
                              "' names no camera of the project (its "
                              "cameras: " +
                              names + ")");
}

ColmapRigRun CalibrateColmapRig(const ColmapCalibrationInputs& inputs,
                                const ColmapProjectCameras& cameras,
                                int reference,
                                const CalibrationProgress& progress) {
  if (reference < 0 || reference >= static_cast<int>(cameras.cameras.size())) {
    throw std::invalid_argument("reference camera index out of range");
  }
  ColmapRigRun rig;
  rig.grouping = cameras.grouping;
  rig.reference = reference;
  int num_run = 0;
  std::string first_error;
  for (const ColmapProjectCamera& camera : cameras.cameras) {
    ColmapRigCameraRun camera_run;
    camera_run.camera = camera;
    camera_run.inputs = inputs;
    camera_run.inputs.camera_ids = camera.camera_ids;
    try {
      camera_run.run = CalibrateColmapProject(
          camera_run.inputs, [&](const std::string& message) {
            if (progress) progress(camera.name + ": " + message);
          });
      ++num_run;
    } catch (const FormatError& error) {
      // This camera's images do not fit the odometry (time stamps outside
      // it, two images at one time): named, the others go on.
      camera_run.input_error = error.what();
      if (first_error.empty()) first_error = error.what();
    }
    rig.cameras.push_back(std::move(camera_run));
  }
  // No camera ran: the project or the odometry is at fault, one error.
  if (num_run == 0) throw FormatError(first_error);

  for (size_t a = 0; a < rig.cameras.size(); ++a) {
    if (!rig.cameras[a].run) continue;
    const auto scales_a = WholeSubModelScales(*rig.cameras[a].run);
    for (size_t b = a + 1; b < rig.cameras.size(); ++b) {
      if (!rig.cameras[b].run) continue;
      const auto scales_b = WholeSubModelScales(*rig.cameras[b].run);
      for (const auto& [sub_model, scale_a] : scales_a) {
        const auto scale_b = scales_b.find(sub_model);
        if (scale_b == scales_b.end()) continue;
        SharedSubModelScale shared;
        shared.camera_a = static_cast<int>(a);
        shared.camera_b = static_cast<int>(b);
        shared.sub_model = sub_model;
        shared.scale_a = scale_a.first;
        shared.scale_b = scale_b->second.first;
        const double sigma = std::hypot(scale_a.second, scale_b->second.second);
        const double difference = shared.scale_b / shared.scale_a - 1.0;
        shared.sigmas =
            sigma > 0.0 ? difference / sigma
                        : std::copysign(std::numeric_limits<double>::infinity(),
                                        difference);
        if (difference == 0.0) shared.sigmas = 0.0;
        rig.shared_scales.push_back(shared);
      }
    }
  }
  AdjustColmapRigJointly(inputs, progress, &rig);
  return rig;
}

void AdjustColmapRigJointly(const ColmapCalibrationInputs& inputs,
                            const CalibrationProgress& progress,
                            ColmapRigRun* rig) {
  if (inputs.joint_adjustment.use == JointAdjustmentUse::kOff) return;
  std::vector<const ColmapCalibrationRun*> runs;
  std::vector<std::string> names;
  for (const ColmapRigCameraRun& camera : rig->cameras) {
    runs.push_back(camera.run ? &*camera.run : nullptr);
    names.push_back(camera.camera.name);
  }
  rig->joint = AdjustRigJointly(runs, names, inputs, progress);
}

std::vector<std::string> SharedScaleWarnings(const ColmapRigRun& rig) {
  std::vector<std::string> warnings;
  for (const SharedSubModelScale& shared : rig.shared_scales) {
    if (!shared.Disagrees()) continue;
    warnings.push_back(
        "cameras " + rig.cameras[shared.camera_a].camera.name + " and " +
        rig.cameras[shared.camera_b].camera.name +
        " disagree on the metric scale of sub-model " +
        (shared.sub_model.empty() ? std::string("0") : shared.sub_model) +
        ": " + FormatRounded(shared.scale_a, 5) + " vs " +
        FormatRounded(shared.scale_b, 5) + " m per unit (" +
        FormatRounded(100.0 * (shared.scale_b / shared.scale_a - 1.0), 2) +
        " %, " + FormatRounded(std::abs(shared.sigmas), 2) +
        " sigma): one model has one scale, so at least one of the two "
        "cameras' calibrations is off by more than its stated uncertainty");
  }
  return warnings;
}

}  // namespace odomcal
