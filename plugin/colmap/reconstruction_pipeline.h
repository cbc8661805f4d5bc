// "Reconstruct and calibrate an image folder with its odometry": the
// pipeline behind `odomcal run`, as a library call. Selects frames with the
// odometry, refuses a drive whose odometry cannot determine the calibration
// (no or too few turns) before COLMAP, runs COLMAP (feature_extractor,
// matching of image pairs chosen along the odometry path (or COLMAP's
// spatial or sequential matcher), mapper, run again with
// another random seed while the odometry contradicts its model, matching
// again when that does not help; mapper_policy.h) in a workspace, then
// calibrates the reconstruction as CalibrateColmapProject does. Finished
// COLMAP stages are reused when rerun on the same workspace.
//
// Nothing is printed; progress goes to a callback. Files are written only
// inside the workspace: COLMAP's (database, logs, mapper attempts), the
// model calibrated (sparse/) and the image list. The calibration outputs
// (calibration.json, report.html, ...) are the caller's to write
// (colmap_calibration_outputs.h, target odomcal::reports).
#pragma once

#include "odomcal/adapters/excitation_precheck.h"
#include "odomcal/adapters/frame_selection.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"
#include "odomcal/plugin/colmap/mapper_chunks.h"
#include "odomcal/plugin/colmap/mapper_policy.h"
#include "odomcal/plugin/colmap/mapper_stretches.h"
#include "odomcal/plugin/output/output_guard.h"

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace odomcal {

// Which structure-from-motion maps the images.
enum class MapperKind {
  kIncremental,  // `colmap mapper`
  // COLMAP's `global_mapper` (GLOMAP inside COLMAP, from 4.0), or before 4.0
  // the standalone `glomap mapper`. The drive is mapped as one model (global
  // SfM has no incremental bundle adjustment to bound by chunks); stretches
  // left unregistered are mapped by `colmap mapper` from the odometry's
  // initial pair, as with the incremental mapper.
  kGlobal,
};
const char* ToString(MapperKind kind);  // "incremental", "global"

struct ReconstructionOptions {
  std::string image_path;  // folder of images (sub-folders too)
  // One camera of a rig: only the images in this sub-folder of image_path
  // (names keep the sub-folder, as the image timestamps list them); empty:
  // every image.
  std::string image_sub_folder;
  std::string workspace_path;  // created; reused on reruns
  std::string camera_model = "PINHOLE";
  std::string camera_params;  // COLMAP order, comma-separated; empty: estimate
  // "odometry" (pairs chosen from the odometry, candidate_pairs;
  // mapper_stretches.h), "spatial" or "sequential"
  std::string matcher = "odometry";
  std::string colmap_path = "colmap";
  // Inputs odomcal itself wrote into the workspace (`odomcal run --bag`
  // extracts the bag into <workspace>/bag_inputs): inputs under it are
  // odomcal's own entry, not guarded as the user's files.
  std::string extracted_inputs_path;
  MapperKind mapper_kind = MapperKind::kIncremental;
  // The standalone GLOMAP, for kGlobal with a COLMAP before 4.0.
  std::string glomap_path = "glomap";
  int max_num_features = 2048;
  int num_threads = 2;
  int spatial_neighbors = 8;
  int sequential_overlap = 10;
  MapperPolicyOptions mapper;
  // Run COLMAP even when the odometry at the image times cannot determine
  // the calibration (excitation_precheck.h); otherwise that is refused
  // before any COLMAP stage, with the solver's status.
  bool force = false;
  FrameSelectionOptions frames;
  // The odometry, image times and calibration options; model_path and
  // database_path are ignored (the pipeline makes them).
  ColmapCalibrationInputs project;
  // Stretches of at least kMinStretchModelImages images that the chosen
  // model left unregistered are matched along the odometry and mapped as
  // models of their own (segments with their own scale; mapper_stretches.h).
  bool map_unregistered_stretches = true;
  CandidatePairOptions candidate_pairs;  // stretches and --matcher odometry
  InitialPairOptions initial_pair;
  // Drives of more selected images than chunks.max_images are mapped in
  // chunks (mapper_chunks.h), each with --random_seed 0 and again with the
  // next seeds only where the odometry finds its model folded, instead of
  // the mapper attempts on all images; smaller drives are mapped as before.
  ChunkOptions chunks;
};

// COLMAP's Mapper.min_model_size default: smaller stretches are not mapped.
inline constexpr int kMinStretchModelImages = 10;

// One step of the pipeline's progress.
struct PipelineProgress {
  enum class Event {
    kStageStarted,   // message: what the stage does
    kStageFinished,  // message: its outcome; seconds: its duration
    kNote,           // message: a line about the run between stages
    // During a COLMAP stage, at most once a second: what COLMAP reports
    // ("matching image 120/300, 45 s, about 68 s left"); seconds: since
    // the stage started; fraction includes the stage's part done.
    kStageProgress,
  };
  Event event = Event::kNote;
  int stage = 0;  // 1 .. num_stages; stages 3 and 4 may run more than once
  int num_stages = 0;
  double fraction = 0.0;  // of the pipeline done, in [0, 1], never decreases
  std::string message;
  double seconds = 0.0;
};

using ProgressCallback = std::function<void(const PipelineProgress&)>;

struct ReconstructionResult {
  // The calibration of the model kept (sub-models, odometry, association,
  // result, metric sub-models, every mapper attempt and the one chosen).
  ColmapCalibrationRun calibration;
  // True when the odometry at the image times cannot determine the
  // calibration and options.force is off: no COLMAP stage ran, and
  // calibration holds only the solver's status and the association.
  bool refused_before_colmap = false;
  std::string model_path;     // workspace/sparse: the model calibrated
  std::string database_path;  // the matches it was mapped from
  // The frame selection's thresholds (automatic ones resolved from the
  // camera's field of view; frame_selection.h).
  FrameSpacing frame_spacing;
  int num_chunks = 0;  // the chunks mapped; 0: one model of all images
};

// The stages of the pipeline, for PipelineProgress::num_stages.
inline constexpr int kReconstructionStages = 5;

// Everything the pipeline writes in its workspace (for ClaimOutputFolder,
// output_folder.h).
std::vector<std::string> ReconstructionWorkspaceEntries();

// The run's inputs that are the user's files, with their flags (for
// CheckOutputsApartFromInputs, output_guard.h): all but those under
// extracted_inputs_path.
std::vector<FlaggedPath> UserInputs(const ReconstructionOptions& run);

// Whether the pipeline takes `path` as an image: .png, .jpg, .jpeg, .bmp,
// .tif, .tiff, in any case.
bool IsImageFile(const std::filesystem::path& path);

// Throws FormatError (inputs), OutputError (workspace), ColmapError (COLMAP
// failed or produced no model) or std::invalid_argument (options), each
// with a one-line message.
ReconstructionResult ReconstructAndCalibrate(
    const ReconstructionOptions& options,
    const ProgressCallback& progress = {});

}  // namespace odomcal
