// Image pairs chosen from the odometry, for matching and for starting COLMAP
// models where the mapper registered nothing.
//
// Matching: COLMAP's spatial matcher pairs each image with its k nearest
// neighbours; at 8 cm spacing, k = 8 spans about +-30 cm, too short a
// baseline for the mapper's initial pair (16 deg triangulation angle) and
// for robust triangulation at room depths (measured in issue 18: 85 of 300
// images registered). Here an image is paired with its 6 nearest images in
// time on each side and, ahead of it along the path, with one image per
// baseline level: the farthest image within max_distance_m / 2^k of path and
// max_view_angle_deg / 2^k of accumulated turn, k = 0 .. baseline_levels-1
// (e.g. 12.5, 25, 50, 100 cm). The levels look ahead only: an image's
// partners behind it are the images whose own levels chose it, the same
// baselines where the spacing is even, fewer where it varies (measured
// coverage in docs/benchmarks.md; a backward scan would add pairs). Geometric
// steps give every image short baselines (reliable matches) and long ones
// (triangulation angle) at a cost that does not grow with the frame rate:
// pairing with every image within 1 m matched 27 pairs per image on the
// 300-image drive, this about 6 (docs/benchmarks.md). The viewing directions of
// a pair differ by at most max_view_angle_deg (the odometry's rotation between
// the two is the camera's, whatever the mounting, so views that far apart still
// overlap within a 60-90 deg field of view). Loop pairs: where the robot
// returns to a place, images close in place and direction but far apart along
// the path; one per image and visit, the closest.
//
// Initial pairs: in a stretch of images the mapper left unregistered, the
// pair to start a model from, chosen from the odometry: a baseline long
// enough to triangulate and a turn between the two, since COLMAP refuses
// initial pairs that moved (nearly) along the optical axis
// (Mapper.init_max_forward_motion), as a robot driving straight does.
#pragma once

#include "odomcal/solver/rigid3.h"

#include <optional>
#include <utility>
#include <vector>

namespace odomcal {

struct CandidatePairOptions {
  double max_distance_m = 1.0;
  double max_view_angle_deg = 30.0;
  // The nearest images in time on each side are always paired (odometry
  // noise or a pure turn must not leave an image without neighbours). 6,
  // measured on the rendered `small` scene (seed 1, matched anew and mapped
  // per trial): with 2 the mapper folded its turn (21 of 33 images
  // calibrated); with 4, 7 of 9 matchings gave a folded model (6 a
  // 12-image duplicate of the turn beside a clean model, 1 the fold inside
  // the only model, for every seed); with 5, 4 of 6; with 6, 0 of 6. In the
  // turn the 5th and 6th neighbours do not overlap (0 inliers), so the gain
  // comes from the pairs they add elsewhere (along the straight parts;
  // presumably a different initial pair, not verified).
  int min_neighbors_each_side = 6;
  // Geometric baseline levels along the path (see the top of this file).
  int baseline_levels = 4;
  // Loop pairs: at most this far apart in place and direction, and at least
  // loop_min_path_m apart along the path.
  double loop_max_distance_m = 0.5;
  double loop_max_view_angle_deg = 20.0;
  double loop_min_path_m = 3.0;
  void Check() const;  // throws std::invalid_argument naming the field
};

// Pairs (i, j), i < j, of `origin_from_odom` poses (one per image, in time
// order), sorted, without repeats.
std::vector<std::pair<int, int>> OdometryCandidatePairs(
    const std::vector<Rigid3d>& origin_from_odom,
    const CandidatePairOptions& options = {});

// The viewing-direction limit for a camera whose horizontal field of view is
// `field_of_view_deg`: at most half of it (so that two views share at least
// half the image) and at most `max_view_angle_deg`.
double ViewAngleLimitDeg(double field_of_view_deg, double max_view_angle_deg);

struct InitialPairOptions {
  double min_baseline_m = 0.2;
  double max_baseline_m = 1.0;
  double min_turn_deg = 8.0;   // preferred: a turn between the two images
  double max_turn_deg = 30.0;  // views still overlap
};

// The initial pair for a stretch, one of `candidates` (so that it has been
// matched): among those with a baseline
// in [min, max] and a turn of at most max_turn_deg, those turning at least
// min_turn_deg first, then the longest baseline, then the one nearest the
// stretch's middle. nullopt when no pair qualifies.
std::optional<std::pair<int, int>> ChooseInitialPair(
    const std::vector<Rigid3d>& origin_from_odom,
    const std::vector<std::pair<int, int>>& candidates,
    const InitialPairOptions& options = {});

}  // namespace odomcal
