// Robot bags on the command line: `odomcal inspect --bag` (what a bag holds
// and what `run` would take from it), `odomcal extract --bag` (the bag as
// odomcal's input files), and the extraction `odomcal run --bag` starts
// with.
#pragma once

#include "odomcal/adapters/bag/bag_extraction.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"

#include <ostream>
#include <string>

namespace odomcal {

int RunInspect(int argc, char** argv);
int RunExtract(int argc, char** argv);

// Extracts the topics of `bag_path` that `options` choose into
// options.output_folder, printing the chosen topics, the progress and the
// summary to `out` (lines indented by two spaces). Throws as ExtractBag.
bag::BagExtractionSummary ExtractBagPrinting(
    const std::string& bag_path,
    const bag::BagExtractionOptions& options,
    std::ostream& out);

// `odomcal run --bag`: the workspace claimed, the bag extracted into
// <workspace>/bag_inputs (replacing an earlier extraction), and `run`
// pointed at the files: images, image times, odometry, and the camera from
// CameraInfo unless `camera_params_given`. Prints as ExtractBagPrinting.
bag::BagExtractionSummary ExtractBagForRun(
    const std::string& bag_path,
    bool camera_params_given,
    bag::BagExtractionOptions* bag_options,
    ReconstructionOptions* run,
    std::ostream& out);

// The input file the extraction wrote for --odometry (odometry.csv,
// odometry.tum or wheels.csv), in options.output_folder.
std::string ExtractedOdometryPath(const bag::BagExtractionOptions& options,
                                  const bag::BagExtractionSummary& summary);

// "--camera_model OPENCV" and "--camera_params 458.6,..." of the extracted
// camera, split: {model, params}; empty when the bag has no CameraInfo.
std::pair<std::string, std::string> ExtractedCamera(
    const bag::BagExtractionSummary& summary);

}  // namespace odomcal
