// Which quantities of the calibration the data determine. Typed: the
// quantity names of the result JSON ("rotation", "translation_x", ...,
// "metric_scale[k]") are made only by UnobservableNames() and ScaleName().
#pragma once

#include <string>
#include <vector>

namespace odomcal {

// How one quantity of the calibration is known.
enum class Determination {
  kEstimated,     // determined by the data, with a standard deviation
  kHeld,          // not estimated: held at a given value (translation z under
                  // planar motion, options.fixed_translation_z_m)
  kUndetermined,  // the data do not determine it: its value is no estimate
};

// Where an estimated translation z comes from.
enum class TranslationZSource {
  kGiven,       // held at options.fixed_translation_z_m
  kMotion,      // SE(3) odometry whose rotation axes are not all parallel
  kFloorPlane,  // the camera's height above the floor (floor_plane.h)
};
// "given", "motion", "floor_plane".
std::string ToString(TranslationZSource source);

struct Observability {
  Determination rotation = Determination::kEstimated;
  Determination translation_x = Determination::kEstimated;
  Determination translation_y = Determination::kEstimated;
  // Planar odometry cannot see z (Guo et al., Section IV-B): held until the
  // solver finds that the (SE(3)) odometry determines it.
  Determination translation_z = Determination::kHeld;
  TranslationZSource translation_z_source = TranslationZSource::kGiven;
  std::vector<Determination> metric_scales;  // one per segment

  // Rotation, x and y all estimated: the extrinsic can be used (z is
  // estimated or held at its given value).
  bool ExtrinsicDetermined() const;
  // Segment k's scale estimated (false for a segment out of range).
  bool ScaleDetermined(size_t segment) const;
  // Nothing held or undetermined but translation z, which may be held.
  bool AllDetermined() const;
  // Everything undetermined (rotation, translation, scales): no estimate.
  static Observability Nothing(int num_segments);
};

// "metric_scale" for a single segment, else "metric_scale[k]".
std::string ScaleName(size_t segment, size_t num_segments);

// The names of the quantities that are not estimated, as the JSON
// `unobservable` lists them: the held ones first, then the undetermined
// ones, each in the order rotation, translation_x, translation_y,
// translation_z, metric scales.
std::vector<std::string> UnobservableNames(const Observability& observability);
// The undetermined ones alone, in the same order.
std::vector<std::string> UndeterminedNames(const Observability& observability);

}  // namespace odomcal
