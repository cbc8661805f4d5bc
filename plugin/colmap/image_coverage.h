// How much of a drive made it into the calibration: of the images selected
// for COLMAP, how many were registered and associated with the odometry
// inside motion pairs of the calibration that the odometry does not
// contradict, per stretch of the drive and overall. A model that registers 85
// of 300 images still calibrates "from 51 of 51 motion pairs"; this is what
// says that it covers 28 % of the drive.
#pragma once

#include "odomcal/adapters/frame_selection.h"

#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace odomcal {

struct ColmapCalibrationRun;  // colmap_calibration.h

// A run of consecutive selected images (time order) that is either in the
// calibration (missing runs shorter than the gap threshold included) or a
// gap: at least that many consecutive images that are not.
struct CoverageStretch {
  bool in_calibration = false;
  int first_image = 0;  // indices into the selected images, inclusive
  int last_image = 0;
  int64_t first_stamp_ns = 0;  // image times of the first and last image
  int64_t last_stamp_ns = 0;
  int num_images = 0;
  int num_registered = 0;      // in some sub-model calibrated
  int num_in_calibration = 0;  // ... and inside a motion pair used
  double Fraction() const;     // num_in_calibration / num_images
};

struct ImageCoverage {
  int num_selected_images = 0;
  int num_registered_images = 0;
  int num_in_calibration = 0;
  // Of the selected images' time span, the part between the first and last
  // image in the calibration of each stretch in the calibration.
  double duration_fraction = 0.0;
  std::vector<CoverageStretch> stretches;  // in time order
  double Fraction() const;  // num_in_calibration / num_selected_images
};

// Missing runs of at least this many images are gaps of their own; shorter
// ones (an image COLMAP could not register between two it did) are counted
// inside the stretch around them.
inline constexpr int kMinCoverageGapImages = 3;

// `selected` in time order; `registered` and `in_calibration` hold image
// names (in_calibration is a subset of registered).
ImageCoverage SummarizeImageCoverage(
    const std::vector<TimedImage>& selected,
    const std::set<std::string>& registered,
    const std::set<std::string>& in_calibration,
    int min_gap_images = kMinCoverageGapImages);

// Names of the images registered in the sub-models calibrated (duplicates
// left out are not calibrated).
std::set<std::string> RegisteredImages(const ColmapCalibrationRun& run);

// Names of the registered images whose odometry time (image time +
// camera_time_offset_ns) lies within a motion pair of the calibration that
// the odometry does not contradict (ContradictsOdometry: a pair used, or
// one beyond only the noise estimated from the data), of the sub-model
// they were registered in.
std::set<std::string> ImagesInCalibration(const ColmapCalibrationRun& run,
                                          int64_t camera_time_offset_ns);

// "85 of 300 selected images (28 %) in the calibration".
std::string CoverageClause(const ImageCoverage& coverage);

// A warning when fewer than `min_fraction` of the selected images are in the
// calibration, naming the gaps.
inline constexpr double kMinCoverageFraction = 0.9;
std::optional<std::string> CoverageWarning(
    const ImageCoverage& coverage, double min_fraction = kMinCoverageFraction);

}  // namespace odomcal
