#include "odomcal/plugin/run_flags.h"

#include "odomcal/plugin/command_line.h"

namespace odomcal {
namespace {

using Run = ReconstructionOptions;

bool Rematches(const Run& run) { return run.mapper.max_matching_rounds > 1; }

}  // namespace

const OptionTable<ReconstructionOptions>& RunFolderFlags() {
  static const OptionTable<Run> table = [] {
    OptionRow<Run> image_path;
    image_path.name = "image_path";
    image_path.help = "folder of images (sub-folders too)";
    image_path.echo_key = "image_path";
    image_path.add = [](CLI::App* app, Run* run) {
      return app
          ->add_option("--image_path",
                       run->image_path,
                       "folder of images (sub-folders too)")
          ->required()
          ->check(CLI::ExistingDirectory);
    };
    image_path.echo = [](const Run& run) {
      return nlohmann::json(run.image_path);
    };
    OptionRow<Run> workspace_path;
    workspace_path.name = "workspace_path";
    workspace_path.help =
        "COLMAP workspace and outputs (created; reused on reruns)";
    workspace_path.add = [](CLI::App* app, Run* run) {
      return app
          ->add_option(
              "--workspace_path",
              run->workspace_path,
              "COLMAP workspace and outputs (created; reused on reruns)")
          ->required();
    };
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
        OptionRow<Run> row;
        row.name = "camera_params";
        row.echo_key = row.name;
        row.help =
            "intrinsics in COLMAP's order, e.g. fx,fy,cx,cy; kept fixed in "
            "the mapper (strongly recommended)";
        row.add = [help = row.help](CLI::App* app, Run* run) {
          return app->add_option("--camera_params", run->camera_params, help);
        };
        row.echo = [](const Run& run) {
          return run.camera_params.empty() ? nlohmann::json(nullptr)
                                           : nlohmann::json(run.camera_params);
        };
        return row;
      }(),
      ChoiceRow<Run>(
          "matcher",
          "spatial: pairs by odometry position (COLMAP 3.8 priors); "
          "sequential: by image name order; odometry: pairs along the "
          "odometry path up to 1 m apart within 30 deg, and loops",
          {"spatial", "sequential", "odometry"},
          [](const Run& run) { return run.matcher; },
          [](Run* run, const std::string& name) { run->matcher = name; }),
      NumberRow<Run>(
          "spatial_neighbors",
          "spatial matcher: neighbours per image",
          [](auto& r) -> auto& { return r.spatial_neighbors; },
          AtLeast(1)),
      NumberRow<Run>(
          "sequential_overlap",
          "sequential matcher: overlap",
          [](auto& r) -> auto& { return r.sequential_overlap; },
          AtLeast(1)),
      NumberRow<Run>(
          "max_num_features",
          "SIFT features per image (matching cost grows with its square)",
          [](auto& r) -> auto& { return r.max_num_features; },
          AtLeast(1)),
      NumberRow<Run>(
          "num_threads",
          "COLMAP threads",
          [](auto& r) -> auto& { return r.num_threads; },
          AtLeast(1)),
      NumberRow<Run>(
          "frame_min_translation_m",
          "frame selection: keep an image once the robot moved this far...",
          [](auto& r) -> auto& { return r.frames.min_translation_m; },
          AtLeast(0)),
      NumberRow<Run>(
          "frame_min_rotation_deg",
          "...or turned this much since the last kept image",
          [](auto& r) -> auto& { return r.frames.min_rotation_deg; },
          AtLeast(0)),
      NumberRow<Run>(
          "mapper_attempts",
          "COLMAP mapper runs (--random_seed 0, 1, ...) while the odometry "
          "contradicts motion pairs of the model; the model it contradicts "
          "least is kept; per matching",
          [](auto& r) -> auto& { return r.mapper.max_seeds; },
          InRange(1, 20)),
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
      SwitchRow<Run>(
          "force",
          "run COLMAP even when the odometry at the image times "
          "cannot determine the calibration (no or too few turns)",
          "force",
          [](auto& r) -> auto& { return r.force; },
          true),
  };
  return table;
}

void AddRunFlags(CLI::App* app, ReconstructionOptions* settings) {
  AddFlags(RunFolderFlags(), app, settings);
  AddFlags(RunFlags(), app, settings);
}

nlohmann::json RunFlagsEcho(const ReconstructionOptions& settings) {
  nlohmann::json echo = {{"inputs", nlohmann::json::object()},
                         {"options", {{"run", nlohmann::json::object()}}}};
  EchoOptions(RunFolderFlags(), settings, &echo["inputs"]);
  EchoOptions(RunFlags(), settings, &echo["options"]["run"]);
  return echo;
}

}  // namespace odomcal
