// See the header. Every file is written to a temporary name and renamed, so
// that a reader never sees half a file.

#include "odomcal/plugin/report/colmap_calibration_outputs.h"

#include "odomcal/adapters/colmap_model.h"
#include "odomcal/adapters/trajectory_io.h"
#include "odomcal/plugin/output/output_file.h"
#include "odomcal/plugin/output/output_folder.h"
#include "odomcal/plugin/report/colmap_report.h"
#include "odomcal/plugin/report/robot_outputs.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

namespace odomcal {

namespace fs = std::filesystem;

std::vector<std::string> ColmapCalibrationOutputEntries() {
  std::vector<std::string> entries = {"calibration.json",
                                      "calibration.yaml",
                                      "sparse_metric",
                                      "camera_in_odom.tum",
                                      "camera_in_odom.tum.tmp",
                                      "report.html",
                                      "cameras"};
  for (const std::string& suffix : RobotOutputSuffixes()) {
    entries.push_back("calibration" + suffix);
  }
  return entries;
}

std::vector<std::string> WriteColmapCalibrationOutputs(
    const ColmapCalibrationRun& run,
    const ReportContext& context,
    const std::string& output_dir) {
  return WriteColmapCalibrationOutputs(run, context, output_dir, nullptr);
}

std::vector<std::string> WriteColmapCalibrationOutputs(
    const ColmapCalibrationRun& run,
    const ReportContext& context,
    const std::string& output_dir,
    const RigOverrides* rig) {
  const fs::path root(output_dir);
  if (rig == nullptr) RemoveOwnedOutput(output_dir, "cameras");
  WriteFileAtomically(
      (root / "calibration.json").string(),
      (rig != nullptr ? rig->result : ColmapCalibrationToJson(run, context))
              .dump(2) +
          "\n");
  WriteFileAtomically((root / "calibration.yaml").string(),
                      CalibrationToYaml(run.check.result));
  std::vector<std::string> entries = {"calibration.json", "calibration.yaml"};

  // The robot outputs of this result; an earlier run's others go.
  std::set<std::string> robot_files;
  const std::optional<RobotDescription> robot =
      rig != nullptr ? rig->robot
                     : RobotDescriptionOf(run.check.result, context);
  if (robot) {
    for (const RobotOutputFile& file : RobotOutputFiles(*robot)) {
      const std::string name = "calibration" + file.suffix;
      WriteFileAtomically((root / name).string(), file.text);
      entries.push_back(name);
      robot_files.insert(name);
    }
  }
  for (const std::string& suffix : RobotOutputSuffixes()) {
    const std::string name = "calibration" + suffix;
    if (robot_files.count(name) == 0) RemoveOwnedOutput(output_dir, name);
  }

  // sparse_metric/<name>: written to a temporary folder, then renamed. An
  // earlier run's sub-models go first: they are not this calibration's.
  const fs::path metric_root = root / "sparse_metric";
  RemoveOwnedOutput(output_dir, "sparse_metric");
  if (!run.metric_models.empty()) {
    fs::create_directories(metric_root);
    entries.push_back("sparse_metric/");
  }
  for (const MetricSubModel& metric : run.metric_models) {
    const fs::path target = metric_root / metric.name;
    const fs::path temporary = metric_root / (metric.name + ".tmp");
    RemoveOwnedOutput(output_dir, "sparse_metric/" + metric.name + ".tmp");
    fs::create_directories(temporary);
    WriteColmapModel(metric.model, temporary.string(), ColmapFormat::kBinary);
    RemoveOwnedOutput(output_dir, "sparse_metric/" + metric.name);
    fs::rename(temporary, target);
  }

  // camera_in_odom.tum: origin_from_cam of every registered image with a
  // time, in metres, each image once.
  Trajectory cameras;
  cameras.source = "camera_in_odom";
  std::set<std::string> written;
  std::map<std::string, int64_t> stamp_of;
  for (const ColmapSegment& segment : run.segments) {
    for (size_t i = 0; i < segment.image_names.size(); ++i) {
      stamp_of.emplace(segment.image_names[i],
                       segment.trajectory.poses[i].stamp_ns);
    }
  }
  for (const MetricSubModel& metric : run.metric_models) {
    for (const auto& [id, image] : metric.model.images) {
      const auto stamp = stamp_of.find(image.name);
      if (stamp == stamp_of.end() || !written.insert(image.name).second)
        continue;
      cameras.poses.push_back({stamp->second, Inverse(image.cam_from_world)});
    }
  }
  std::sort(cameras.poses.begin(),
            cameras.poses.end(),
            [](const StampedPose& a, const StampedPose& b) {
              return a.stamp_ns < b.stamp_ns;
            });
  const std::string tum_path = (root / "camera_in_odom.tum").string();
  const std::string tum_temporary = tum_path + ".tmp";
  RemoveOwnedOutput(output_dir, "camera_in_odom.tum");
  if (!cameras.poses.empty()) {
    WriteTumTrajectory(cameras, tum_temporary);
    fs::rename(tum_temporary, tum_path);
    entries.push_back("camera_in_odom.tum");
  }

  WriteFileAtomically((root / "report.html").string(),
                      ColmapReportHtml(run, context, rig));
  entries.push_back("report.html");
  return entries;
}

}  // namespace odomcal
