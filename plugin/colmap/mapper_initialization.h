// How COLMAP's incremental mapper starts a model, and what `odomcal run`
// tries when it starts none.
//
// COLMAP's mapper begins with one image pair that passes three tests
// (IncrementalMapper::EstimateInitialTwoViewGeometry, 3.8 to 4.1): at least
// Mapper.init_min_num_inliers (100) inliers, a baseline that is not mostly
// along the first camera's axis (|t_z| of the unit baseline below
// Mapper.init_max_forward_motion, 0.95), and a median triangulation angle
// above Mapper.init_min_tri_angle (16 deg); when no pair passes it halves
// the inliers and the angle twice and then gives up ("No good initial image
// pair found"). It never relaxes the forward-motion test, so a forward
// camera on a road, whose straights are all forward motion, may have no
// pair to start from although its images match well; and which pair it
// finds first depends on the order of the image ids, which COLMAP's
// multi-threaded feature extraction assigns differently from run to run.
//
// The odometry knows where each image was taken: RankInitialPairs scores the
// verified pairs of the database by their inliers and the baseline the
// odometry gives them, sideways to the camera (the essential matrix the
// matcher verified gives the baseline's direction in the camera, and so
// COLMAP's forward-motion test, before any mapper run). When a mapper run
// gives no model, InitializationLadder lists what is tried next, in this
// order:
//   1. the odometry's best pair, passed as Mapper.init_image_id1/2, with
//      COLMAP's default tests;
//   2. the odometry's next best pairs (up to kMaxOdometryPairs in all);
//   3. COLMAP's own pair search with the tests relaxed
//      (kRelaxedInitialization: forward motion accepted, inliers and angle
//      from half the defaults, which COLMAP halves twice more);
//   4. the odometry's best pair with the tests relaxed;
//   5. (a drive mapped in chunks) the chunk with its neighbours' images,
//      COLMAP's own search, tests relaxed.
// Each rung is one mapper run; a run that finds no initial pair ends within
// seconds, so the ladder costs little where it is not needed.
#pragma once

#include "odomcal/solver/rigid3.h"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct ColmapVerifiedPair;

// One image the mapper may start from: its database id and name, and the
// odometry's pose at its time (none outside the log or in a gap).
struct InitialPairImage {
  uint32_t image_id = 0;
  std::string name;
  std::optional<Rigid3d> origin_from_odom;
};

struct InitialPairCandidate {
  uint32_t image_id1 = 0;
  uint32_t image_id2 = 0;
  std::string name1;
  std::string name2;
  int num_inliers = 0;
  double baseline_m = 0.0;          // between the odometry poses
  double heading_change_deg = 0.0;  // the odometry's rotation angle
  // |t_z| of the unit baseline in the second camera, from the verified
  // essential matrix (COLMAP's forward-motion test); none without one.
  std::optional<double> forward_motion;
  // num_inliers * baseline_m * sqrt(1 - forward_motion^2): inliers times
  // the baseline across the view, which the triangulation angle grows with.
  double score = 0.0;
};

struct InitialPairTests {
  int min_inliers = 100;             // COLMAP's Mapper.init_min_num_inliers
  double max_forward_motion = 0.95;  // COLMAP's Mapper.init_max_forward_motion
  // Throws std::invalid_argument naming the bad field.
  void Check() const;
};

// The pairs of `verified` between two of `images` (other ids are ignored)
// with odometry poses for both, at least options.min_inliers inliers, a
// baseline, and (where the essential matrix tells) forward motion below
// options.max_forward_motion; best score first, ties by image ids.
std::vector<InitialPairCandidate> RankInitialPairs(
    const std::vector<InitialPairImage>& images,
    const std::vector<ColmapVerifiedPair>& verified,
    const InitialPairTests& options);

// |t_z| of the unit baseline that x2^T E x1 = 0 implies for the second
// camera: E = [t]x R, so t spans E's left null space.
double ForwardMotionOfEssential(const Eigen::Matrix3d& essential);

// One way to start the mapper.
struct MapperInitialization {
  enum class Kind {
    kColmapSearch,         // COLMAP's own search, default tests
    kOdometryPair,         // `pair` passed to COLMAP, default tests
    kRelaxedSearch,        // COLMAP's own search, tests relaxed
    kRelaxedOdometryPair,  // `pair`, tests relaxed
    kNeighbourWindow,      // the chunk and its neighbours' images, relaxed
  };
  Kind kind = Kind::kColmapSearch;
  std::optional<InitialPairCandidate> pair;  // the k*OdometryPair kinds

  // The mapper options this adds to a `colmap mapper` command line (their
  // names are the same from COLMAP 3.8 to 4.1).
  std::vector<std::string> MapperArguments() const;
  // "COLMAP's initial pair search", "initial pair 000012.png and
  // 000031.png from the odometry (2.10 m, 41.0 deg, 812 inliers)", ...
  std::string Describe() const;
};

// "colmap_search", "odometry_pair", "relaxed_search",
// "relaxed_odometry_pair", "neighbour_window" (the result JSON's names).
std::string ToString(MapperInitialization::Kind kind);

// The relaxed tests: forward motion accepted (COLMAP requires |t_z| < 1.0,
// i.e. anything but exact forward motion), and the inliers and angle from
// half COLMAP's defaults (COLMAP halves both twice more before it gives up).
struct RelaxedInitialization {
  static constexpr double kMaxForwardMotion = 1.0;
  static constexpr int kMinNumInliers = 50;
  static constexpr double kMinTriAngleDeg = 8.0;
};

inline constexpr int kMaxOdometryPairs = 3;

// The rungs tried after COLMAP's own search gave no model, in the order of
// this file's comment. `default_candidates` are RankInitialPairs with the
// default tests, `relaxed_candidates` with the forward-motion test relaxed;
// `with_neighbour_window`: the drive is mapped in chunks.
std::vector<MapperInitialization> InitializationLadder(
    const std::vector<InitialPairCandidate>& default_candidates,
    const std::vector<InitialPairCandidate>& relaxed_candidates,
    bool with_neighbour_window);

// Why a mapper run whose log is at `log_path` gave no model, from the lines
// COLMAP printed: "no initial image pair passed COLMAP's tests (No good
// initial image pair found)", "the initial pair failed COLMAP's tests", a
// failed CHECK, or the log's last line. "" when the log cannot be read.
std::string MapperFailureCause(const std::string& log_path);

}  // namespace odomcal
