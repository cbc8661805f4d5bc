// Odometry-aware frame selection before SfM: keeps an image only once the
// robot has moved enough since the last kept one, so frames taken while the
// robot stands still (no baseline, wasted matching time) and near-duplicates
// are dropped before COLMAP runs. Images outside the odometry (no time, or
// outside its span, or in a gap) cannot be calibrated and are dropped too.
//
// The spacing can be chosen for triangulation (issue 18: images 8 cm apart
// left the mapper without baseline): with kAutomaticFrameSpacing ("auto" on
// the command line) both thresholds follow from the camera's field of view F,
// the narrower of the horizontal and vertical ones (AutomaticFrameSpacing):
// how the camera is rolled on its mount is what the calibration measures, so
// a turn or a sideways step may sweep either image axis (a portrait camera's
// turns sweep its short side):
//   min_rotation_deg  = F / 8: consecutive kept images share 7/8 of the view,
//                       so a matching window of 4 images on each side (the
//                       nearest images the odometry matcher always pairs;
//                       COLMAP's spatial matcher's 8 neighbours) still
//                       shares half of it while the robot turns;
//   min_translation_m = d * tan(F / 16), d = kTypicalSceneDepthM: each step
//                       adds a triangulation angle of F / 16 at the typical
//                       depth, so that the 4-image window spans F / 4 (12-16
//                       deg for a 50-63 deg camera, about the mapper's
//                       initial-pair angle Mapper.init_min_tri_angle, 16
//                       deg) while a sideways step still keeps 15/16 of the
//                       view.
// The odometry measures the robot's translation and rotation between images.
// The default: on the rendered long drives (320x240, 63 x 50
// deg) it keeps about half the images the fixed 5 cm / 3 deg kept and runs
// several times faster at an extrinsic within the stated uncertainty
// (docs/benchmarks.md). Fixed thresholds remain for drives that need every
// image.
#pragma once

#include "odomcal/adapters/trajectory.h"

#include <cstdint>
#include <string>
#include <vector>

namespace odomcal {

// A threshold from the field of view:
// AutomaticFrameSpacing(field_of_view_deg).
inline constexpr double kAutomaticFrameSpacing = -1.0;
// The depth the automatic translation threshold triangulates at: what an
// indoor robot's camera sees (walls of 4-6 m rooms, 1-4 m away).
inline constexpr double kTypicalSceneDepthM = 2.5;
// COLMAP's focal length when none is given, 1.2 * max(width, height), gives
// the image's longer side a field of view of 2 atan(1 / 2.4) = 45.24 deg
// whatever the size (used when the intrinsics are not given: the aspect is
// then unknown).
inline constexpr double kColmapDefaultFieldOfViewDeg = 45.24;

struct FrameSpacing {
  double min_translation_m = 0.0;
  double min_rotation_deg = 0.0;
};

// F / 8 and kTypicalSceneDepthM * tan(F / 16) (see above); F in (0, 180).
FrameSpacing AutomaticFrameSpacing(double field_of_view_deg);

// The field of view of a pinhole camera along one image axis, with focal
// length `focal_px` and the principal point `principal_point_px` from that
// axis' first pixel edge (the image is about twice as long): 2 atan(c / f).
double FieldOfViewDeg(double focal_px, double principal_point_px);

struct FrameSelectionOptions {
  // kAutomaticFrameSpacing: from field_of_view_deg (AutomaticFrameSpacing).
  double min_translation_m = kAutomaticFrameSpacing;  // keep once moved...
  double min_rotation_deg = kAutomaticFrameSpacing;   // ...or turned this
  // The camera's narrower field of view (horizontal or vertical).
  double field_of_view_deg = kColmapDefaultFieldOfViewDeg;
  // As AssociationOptions' (0: automatic, from the odometry's sampling).
  double max_odometry_gap_s = 0.0;
  int64_t camera_time_offset_ns = 0;  // odometry time = image time + offset
  void Check() const;  // throws std::invalid_argument naming the field
};

struct TimedImage {
  std::string name;
  int64_t stamp_ns = 0;
};

// The thresholds `options` stand for (automatic ones resolved).
FrameSpacing ResolvedFrameSpacing(const FrameSelectionOptions& options);

struct FrameSelection {
  std::vector<TimedImage> kept;  // in time order
  FrameSpacing spacing;          // the thresholds used
  int num_images = 0;
  int num_outside_odometry = 0;
  int num_dropped_still_or_close = 0;
};

// `images` in any order; the result is sorted by time.
FrameSelection SelectFrames(std::vector<TimedImage> images,
                            const Trajectory& odometry,
                            const FrameSelectionOptions& options);

}  // namespace odomcal
