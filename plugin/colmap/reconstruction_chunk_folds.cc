// A chunk's folded stretches posed again from the odometry, triangulated
// and adjusted by COLMAP (reconstruction_stages.h, fold_reposing.h).
#include "odomcal/adapters/colmap_model.h"
#include "odomcal/plugin/colmap/fold_reposing.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"
#include "odomcal/plugin/output/output_folder.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

namespace odomcal::reconstruction {

namespace fs = std::filesystem;

namespace {

// A posed image must see at least this many triangulated points after the
// adjustment: COLMAP's mapper registers an image from 30 inliers
// (--Mapper.abs_pose_min_num_inliers).
constexpr int kMinPointsOfPosedImage = 30;

// Whether the files of model folders `a` and `b` are byte for byte the same
// (false when either is missing).
bool SameModelFiles(const fs::path& a, const fs::path& b) {
  for (const char* name : {"cameras.bin", "images.bin", "points3D.bin"}) {
    std::ifstream file_a(a / name, std::ios::binary);
    std::ifstream file_b(b / name, std::ios::binary);
    if (!file_a || !file_b) return false;
    const std::string bytes_a((std::istreambuf_iterator<char>(file_a)),
                              std::istreambuf_iterator<char>());
    const std::string bytes_b((std::istreambuf_iterator<char>(file_b)),
                              std::istreambuf_iterator<char>());
    if (bytes_a != bytes_b) return false;
  }
  return true;
}

// The earliest stretch of input segment `segment` left out as folded, with
// what posing it from the odometry needs from `calibration`; nothing without
// such a stretch or without an estimate. A segment folded whole has no
// scale: its posed images keep metres as units (any scale is a gauge for a
// model posed whole, which the calibration then scales anew).
std::optional<FoldToRepose> FoldOfSegment(
    const ColmapCalibrationRun& calibration, int segment) {
  const StretchCheckResult& check = calibration.check;
  if (!check.result.has_estimate) return std::nullopt;
  std::optional<FoldToRepose> fold;
  for (const InconsistentStretch& stretch : check.stretches) {
    if (stretch.kept_as_segment || stretch.input_segment != segment ||
        (fold && fold->first_stamp_ns <= stretch.first_stamp_ns)) {
      continue;
    }
    fold = FoldToRepose{};
    fold->first_stamp_ns = stretch.first_stamp_ns;
  }
  if (!fold) return std::nullopt;
  for (size_t o = 0; o < check.input_segment_of_output_segment.size(); ++o) {
    if (check.input_segment_of_output_segment[o] == segment) {
      fold->metres_per_unit = check.result.metric_scales.at(o);
      break;
    }
  }
  if (!(fold->metres_per_unit > 0.0) || !std::isfinite(fold->metres_per_unit)) {
    return std::nullopt;
  }
  fold->camera_time_offset_ns = calibration.systematics.camera_time_offset_ns;
  fold->odom_from_cam = check.result.odom_from_cam;
  fold->max_odometry_gap_s = calibration.association.max_odometry_gap_s;
  return fold;
}

}  // namespace

// Chunk k's sub-models in `chosen`, each with a stretch left out as folded
// posed again from the odometry (fold_reposing.h), then `colmap
// point_triangulator` and `colmap bundle_adjuster` on it (intrinsics held
// as the mapper holds them), written as chunk k's model
// mapper_attempts/<entry> (its other sub-models copied unchanged). Returns
// the number of sub-models posed again (0: none could be, or COLMAP failed
// on one; `why` says which).
int PoseChunkFoldsFromOdometry(ColmapRunner* colmap,
                               const ReconstructionOptions& run,
                               const MatchingRound& round,
                               const ColmapCalibrationRun& calibration,
                               const ChunkCombination& chosen,
                               size_t k,
                               const std::string& entry,
                               std::string* why) {
  const fs::path combined = fs::path(run.workspace_path) / chosen.entry;
  const fs::path root = MapperOutput(run, entry);
  std::error_code error;
  fs::create_directories(root, error);
  const bool fixed_intrinsics = !run.camera_params.empty();
  int num_written = 0;
  int num_posed = 0;
  std::vector<std::string> notes;
  for (size_t sub = 0; sub < chosen.chunk_of_sub_model.size(); ++sub) {
    if (chosen.chunk_of_sub_model[sub] != static_cast<int>(k)) continue;
    const fs::path source = combined / std::to_string(sub);
    const std::string number = std::to_string(num_written++);
    const fs::path target = root / number;
    int segment = -1;
    for (size_t i = 0; i < calibration.segments.size(); ++i) {
      if (calibration.segments[i].sub_model == std::to_string(sub)) {
        segment = static_cast<int>(i);
      }
    }
    const std::optional<FoldToRepose> fold =
        FoldOfSegment(calibration, segment);
    const std::optional<ReposedModel> reposed =
        fold ? ReposeFoldFromOdometry(ReadColmapModel(source.string()),
                                      calibration.segments[segment],
                                      calibration.odometry,
                                      *fold)
             : std::nullopt;
    const fs::path entry_path = fs::path("mapper_attempts") / entry;
    if (!reposed) {
      RemoveOwnedOutput(run.workspace_path, (entry_path / number).string());
      fs::copy(source, target, fs::copy_options::recursive);
      continue;
    }
    // Stage reuse compares the arguments, not the posed model they read: a
    // model posed differently (another calibration) runs both stages anew.
    const fs::path posed = root / ("posed_" + number);
    const fs::path posed_new = root / ("posed_" + number + ".new");
    const fs::path triangulated = root / ("triangulated_" + number);
    WriteColmapModel(reposed->model, posed_new.string(), ColmapFormat::kBinary);
    if (!SameModelFiles(posed, posed_new)) {
      for (const std::string& stale : {"triangulated_" + number, number}) {
        RemoveOwnedOutput(run.workspace_path, (entry_path / stale).string());
      }
      fs::remove_all(posed, error);
      fs::rename(posed_new, posed);
    } else {
      fs::remove_all(posed_new, error);
    }
    fs::create_directories(triangulated, error);
    fs::create_directories(target, error);
    const std::string stage = entry + "_" + number;
    try {
      colmap->RunStage("triangulate_" + stage,
                       {"point_triangulator",
                        "--database_path",
                        round.database,
                        "--image_path",
                        run.image_path,
                        "--input_path",
                        posed.string(),
                        "--output_path",
                        triangulated.string(),
                        "--clear_points",
                        "1"},
                       {(triangulated / "images.bin").string()});
      colmap->RunStage("adjust_" + stage,
                       {"bundle_adjuster",
                        "--input_path",
                        triangulated.string(),
                        "--output_path",
                        target.string(),
                        "--BundleAdjustment.refine_focal_length",
                        fixed_intrinsics ? "0" : "1",
                        "--BundleAdjustment.refine_principal_point",
                        "0",
                        "--BundleAdjustment.refine_extra_params",
                        fixed_intrinsics ? "0" : "1"},
                       {(target / "images.bin").string()});
    } catch (const ColmapError& failure) {
      *why = failure.what();
      return 0;
    }
    if (!DetectColmapModelFormat(target.string())) {
      *why = "colmap bundle_adjuster wrote no model to " + target.string();
      return 0;
    }
    // The images must hold their new poses on their own: where the
    // adjustment has too few points to move an image, its pose would be the
    // odometry's, and its motion pairs would agree with the odometry by
    // construction.
    const ColmapModel adjusted = ReadColmapModel(target.string());
    for (const uint32_t id : reposed->reposed_image_ids) {
      const auto image = adjusted.images.find(id);
      int observations = 0;
      if (image != adjusted.images.end()) {
        for (const ColmapPoint2D& point : image->second.points2D) {
          observations += point.point3D_id != kColmapNoPoint3D ? 1 : 0;
        }
      }
      if (observations < kMinPointsOfPosedImage) {
        *why = reposed->model.images.at(id).name + " sees only " +
               std::to_string(observations) +
               " triangulated points after the adjustment (COLMAP's mapper "
               "registers an image from " +
               std::to_string(kMinPointsOfPosedImage) + ")";
        return 0;
      }
    }
    ++num_posed;
    notes.push_back(std::to_string(reposed->num_reposed) + " images from " +
                    reposed->anchor_image + " on");
  }
  // Sub-models a run before this one wrote beyond this chunk's.
  std::vector<std::string> stale;
  for (const auto& item : fs::directory_iterator(root, error)) {
    const std::string name = item.path().filename().string();
    if (SubModelNumber(name) >= num_written) stale.push_back(name);
  }
  for (const std::string& name : stale) {
    RemoveOwnedOutput(run.workspace_path,
                      (fs::path("mapper_attempts") / entry / name).string());
  }
  if (num_posed == 0) {
    *why = calibration.check.result.has_estimate
               ? "no folded stretch of it starts at an image with an "
                 "odometry pose"
               : "the calibration of the chunks' models has no estimate to "
                 "pose it with";
  } else {
    std::string list;
    for (const std::string& note : notes) {
      list += (list.empty() ? "" : "; ") + note;
    }
    *why = list;
  }
  return num_posed;
}

}  // namespace odomcal::reconstruction
