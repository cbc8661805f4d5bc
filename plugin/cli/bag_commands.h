// Robot bags on the command line: `odomcal inspect --bag` (what a bag holds
// and what `run` would take from it), `odomcal extract --bag` (the bag as
// odomcal's input files), and the extraction `odomcal run --bag` starts
// with.
#pragma once

#include "odomcal/adapters/bag/bag_extraction.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"

#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace odomcal {

int RunInspect(int argc, char** argv);
int RunExtract(int argc, char** argv);

// The topics of `bag_path` that `options` choose (bag::ChooseTopics on its
// index). Throws as ChooseTopics and OpenBag.
bag::ChosenTopics ChooseBagTopics(const std::string& bag_path,
                                  const bag::BagExtractionOptions& options);

// Extracts the topics of `bag_path` that `options` choose (`chosen`, when
// given, is that choice, made already) into options.output_folder,
// printing the chosen topics, the progress and the summary to `out` (lines
// indented by two spaces). Throws as ExtractBag.
bag::BagExtractionSummary ExtractBagPrinting(
    const std::string& bag_path,
    const bag::BagExtractionOptions& options,
    std::ostream& out,
    const bag::ChosenTopics* chosen = nullptr);

// `odomcal run --bag` of one camera: the workspace claimed, the bag
// extracted into <workspace>/bag_inputs (replacing an earlier extraction),
// and `run` pointed at the files: images, image times, odometry, and the
// camera from CameraInfo unless `camera_params_given`. Prints as
// ExtractBagPrinting. A rig's options are refused (ExtractBagRigForRun).
bag::BagExtractionSummary ExtractBagForRun(
    const std::string& bag_path,
    bool camera_params_given,
    bag::BagExtractionOptions* bag_options,
    ReconstructionOptions* run,
    std::ostream& out);

// The camera flags of `run --bag` on a rig, as given.
struct BagRigFlags {
  std::vector<std::string> camera_params;  // NAME=PARAMS, or one PARAMS
  std::string reference_camera;            // "": the first
};

// What RunRigReconstruction takes for a rig extracted from a bag.
struct BagRigCameras {
  std::vector<std::string> names;  // in name order
  // NAME=PARAMS for every camera: the user's --camera_params, else its
  // CameraInfo's.
  std::vector<std::string> camera_params;
  // name -> COLMAP model, for the cameras whose parameters come from their
  // CameraInfo (the others take --camera_model).
  std::map<std::string, std::string> camera_models;
};

// `odomcal run --bag` with several image topics (or --rig): as
// ExtractBagForRun, each camera's images in <workspace>/bag_inputs/images/
// <name>/ and one image_timestamps.csv. Before anything is written, throws
// std::invalid_argument naming the topic for a camera with neither a
// CameraInfo nor --camera_params, and as RigCameraParams for
// --camera_params and --reference_camera naming no camera.
BagRigCameras ExtractBagRigForRun(const std::string& bag_path,
                                  const BagRigFlags& flags,
                                  bag::BagExtractionOptions* bag_options,
                                  ReconstructionOptions* run,
                                  std::ostream& out);

// The input file the extraction wrote for --odometry (odometry.csv,
// odometry.tum or wheels.csv), in options.output_folder.
std::string ExtractedOdometryPath(const bag::BagExtractionOptions& options,
                                  const bag::BagExtractionSummary& summary);

// "--camera_model OPENCV" and "--camera_params 458.6,..." of an extracted
// camera, split: {model, params}; empty when it has no CameraInfo.
std::pair<std::string, std::string> ExtractedCamera(
    const bag::CameraExtractionSummary& camera);

}  // namespace odomcal
