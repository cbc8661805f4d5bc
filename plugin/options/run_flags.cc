#include "odomcal/plugin/options/run_flags.h"

#include "odomcal/plugin/options/project_flags.h"

#include <cstdlib>

namespace odomcal {
namespace {

using Run = ReconstructionOptions;

// A frame-selection threshold: "auto" (kAutomaticFrameSpacing, from the
// camera's field of view; frame_selection.h) or a number >= 0. Echoed as
// the value used (run_command.cc resolves "auto" before the echo).
template <typename Field>
OptionRow<Run> FrameSpacingRow(std::string name,
                               std::string help,
                               Field field) {
  return AutoOrNumberRow<Run>(std::move(name),
                              std::move(help),
                              field,
                              kAutomaticFrameSpacing,
                              AutoOrNumberLimit{0.0, true});
}

bool Rematches(const Run& run) { return run.mapper.max_matching_rounds > 1; }

}  // namespace

const OptionTable<ReconstructionOptions>& RunFolderFlags() {
  static const OptionTable<Run> table = [] {
    OptionRow<Run> image_path = NumberRow<Run>(
        "image_path",
        "folder of images (sub-folders too)",
        [](auto& r) -> auto& { return r.image_path; },
        FlagCheck::ExistingDirectory());
    image_path.required = true;
    image_path.show_default = false;
    OptionRow<Run> workspace_path = NumberRow<Run>(
        "workspace_path",
        "COLMAP workspace and outputs (created; reused on reruns)",
        [](auto& r) -> auto& { return r.workspace_path; });
    workspace_path.required = true;
    workspace_path.show_default = false;
    workspace_path.echo = nullptr;  // where the outputs go
    return OptionTable<Run>{image_path, workspace_path};
  }();
  return table;
}

const OptionTable<ReconstructionOptions>& RunFlags() {
  static const OptionTable<Run> table = {
      ChoiceRow<Run>(
          "camera_model",
          "COLMAP camera model",
          {"SIMPLE_PINHOLE",
           "PINHOLE",
           "SIMPLE_RADIAL",
           "RADIAL",
           "OPENCV",
           "OPENCV_FISHEYE",
           "FULL_OPENCV"},
          [](const Run& run) { return run.camera_model; },
          [](Run* run, const std::string& name) { run->camera_model = name; }),
      [] {
        // No default: without it the mapper estimates the intrinsics.
        OptionRow<Run> row = NumberRow<Run>(
            "camera_params",
            "intrinsics in COLMAP's order, e.g. fx,fy,cx,cy; kept fixed in "
            "the mapper (strongly recommended)",
            [](auto& r) -> auto& { return r.camera_params; });
        row.show_default = false;
        row.echo = [](const Run& run) {
          return run.camera_params.empty() ? nlohmann::json(nullptr)
                                           : nlohmann::json(run.camera_params);
        };
        return row;
      }(),
      ChoiceRow<Run>(
          "matcher",
          "odometry: pairs along the odometry path at geometric "
          "baselines up to 1 m, views at most half the field of view (and "
          "30 deg) apart, and loops; spatial: pairs "
          "by odometry position (position priors in the database); sequential: "
          "by image "
          "name order",
          {"odometry", "spatial", "sequential"},
          [](const Run& run) { return run.matcher; },
          [](Run* run, const std::string& name) { run->matcher = name; }),
      NumberRow<Run>(
          "spatial_neighbors",
          "spatial matcher: neighbours per image",
          [](auto& r) -> auto& { return r.spatial_neighbors; },
          FlagCheck::AtLeast(1)),
      NumberRow<Run>(
          "sequential_overlap",
          "sequential matcher: overlap",
          [](auto& r) -> auto& { return r.sequential_overlap; },
          FlagCheck::AtLeast(1)),
      NumberRow<Run>(
          "max_num_features",
          "SIFT features per image (matching cost grows with its square)",
          [](auto& r) -> auto& { return r.max_num_features; },
          FlagCheck::AtLeast(1)),
      NumberRow<Run>(
          "num_threads",
          "COLMAP threads; a drive mapped in chunks maps up to this many "
          "chunks side by side, the threads shared among them",
          [](auto& r) -> auto& { return r.num_threads; },
          FlagCheck::AtLeast(1)),
      FrameSpacingRow(
          "frame_min_translation_m",
          "frame selection: keep an image once the robot moved "
          "this far (auto: 2.5 m * tan(F / 16), F the camera's narrower "
          "field of view)...",
          [](auto& r) -> auto& { return r.frames.min_translation_m; }),
      FrameSpacingRow(
          "frame_min_rotation_deg",
          "...or turned this much since the last kept image "
          "(auto: F / 8)",
          [](auto& r) -> auto& { return r.frames.min_rotation_deg; }),
      NumberRow<Run>(
          "mapper_attempts",
          "COLMAP mapper runs (--random_seed 0, 1, ...) while the odometry "
          "contradicts motion pairs of the model; the model it contradicts "
          "least is kept; per matching (a drive in chunks: per chunk, while "
          "its model is folded)",
          [](auto& r) -> auto& { return r.mapper.max_seeds; },
          FlagCheck::InRange(1, 20)),
      // --rematch on|off sets the matchings at most (2: match again once,
      // 1: never) and is echoed as the boolean "rematch".
      [] {
        OptionRow<Run> row = ChoiceRow<Run>(
            "rematch",
            "when the mapper's seeds do not give a model the odometry "
            "accepts, match the images again and map the new matches too",
            {"on", "off"},
            [](const Run& run) {
              return std::string(Rematches(run) ? "on" : "off");
            },
            [](Run* run, const std::string& name) {
              run->mapper.max_matching_rounds = name == "on" ? 2 : 1;
            });
        row.echo = [](const Run& run) {
          return nlohmann::json(Rematches(run));
        };
        return row;
      }(),
      NumberRow<Run>(
          "colmap_path", "the colmap executable", [](auto& r) -> auto& {
            return r.colmap_path;
          }),
      ChoiceRow<Run>(
          "mapper",
          "incremental: COLMAP's mapper; global: COLMAP's global_mapper "
          "(COLMAP 4.0 and later) or, with an older COLMAP, the standalone "
          "glomap, the drive mapped as one model",
          {"incremental", "global"},
          [](const Run& run) { return std::string(ToString(run.mapper_kind)); },
          [](Run* run, const std::string& name) {
            run->mapper_kind = name == "global" ? MapperKind::kGlobal
                                                : MapperKind::kIncremental;
          }),
      NumberRow<Run>(
          "glomap_path",
          "the glomap executable (--mapper global with a COLMAP before 4.0)",
          [](auto& r) -> auto& { return r.glomap_path; }),
      SwitchRow<Run>(
          "force",
          "run COLMAP even when the odometry at the image times "
          "cannot determine the calibration (no or too few turns)",
          "force",
          [](auto& r) -> auto& { return r.force; },
          true),
      [] {
        OptionRow<Run> row = NumberRow<Run>(
            "chunk_images",
            "drives of more selected images are mapped in chunks of at most "
            "this many, sharing " +
                std::to_string(ChunkOptions().overlap) +
                " images, each a sub-model with its own scale (the mapper's "
                "cost bounded per chunk; a chunk COLMAP folds is mapped "
                "again with the next seeds); 0: one model",
            [](auto& r) -> auto& { return r.chunks.max_images; });
        // Twice the overlap at least (ChunkOptions::Check).
        row.check = FlagCheck::Custom([](const std::string& text) {
          char* end = nullptr;
          const long value = std::strtol(text.c_str(), &end, 10);
          // Not an integer ("1e3"): the integer flag's own error says so.
          if (end == text.c_str() || *end != '\0') return std::string();
          return value == 0 || value >= 2L * ChunkOptions().overlap
                     ? std::string()
                     : "must be 0 or >= " +
                           std::to_string(2 * ChunkOptions().overlap) +
                           ", got " + text;
        });
        return row;
      }(),
  };
  return table;
}

nlohmann::json RunFlagsEcho(const ReconstructionOptions& settings) {
  nlohmann::json echo = {{"inputs", nlohmann::json::object()},
                         {"options", {{"run", nlohmann::json::object()}}}};
  EchoOptions(RunFolderFlags(), settings, &echo["inputs"]);
  EchoOptions(RunFlags(), settings, &echo["options"]["run"]);
  return echo;
}

nlohmann::json RunResultFlagsEcho(const ReconstructionOptions& options,
                                  const ReconstructionResult& result) {
  ColmapCalibrationInputs calibrated = options.project;
  calibrated.model_path = result.model_path;
  calibrated.database_path = result.database_path;
  nlohmann::json echo = ProjectFlagsEcho(calibrated);
  ReconstructionOptions used = options;
  used.frames.min_translation_m = result.frame_spacing.min_translation_m;
  used.frames.min_rotation_deg = result.frame_spacing.min_rotation_deg;
  MergeFlagEcho(RunFlagsEcho(used), &echo);
  return echo;
}

}  // namespace odomcal
