#include "odomcal/adapters/frame_selection.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "odomcal/adapters/association.h"

namespace odomcal {

void FrameSelectionOptions::Check() const {
  if (!(min_translation_m >= 0.0) || !(min_rotation_deg >= 0.0) ||
      !std::isfinite(min_translation_m) || !std::isfinite(min_rotation_deg)) {
    throw std::invalid_argument(
        "frame selection thresholds must be finite and >= 0");
  }
  if (!(max_odometry_gap_s > 0.0) || !std::isfinite(max_odometry_gap_s)) {
    throw std::invalid_argument("max_odometry_gap_s must be finite and > 0");
  }
}

FrameSelection SelectFrames(std::vector<TimedImage> images,
                            const Trajectory& odometry,
                            const FrameSelectionOptions& options) {
  options.Check();
  std::stable_sort(images.begin(), images.end(),
                   [](const TimedImage& a, const TimedImage& b) {
                     return a.stamp_ns < b.stamp_ns;
                   });
  FrameSelection selection;
  selection.num_images = static_cast<int>(images.size());
  constexpr double kDegToRad = 3.14159265358979323846 / 180.0;
  bool have_last = false;
  Rigid3d last;
  for (const TimedImage& image : images) {
    InterpolationFailure why;
    const auto pose = InterpolateOdometry(
        odometry, image.stamp_ns + options.camera_time_offset_ns,
        options.max_odometry_gap_s, &why);
    if (!pose) {
      ++selection.num_outside_odometry;
      continue;
    }
    if (have_last) {
      const Rigid3d motion = Inverse(last) * *pose;
      if (motion.translation.norm() < options.min_translation_m &&
          RotationAngle(motion.rotation) < options.min_rotation_deg * kDegToRad) {
        ++selection.num_dropped_still_or_close;
        continue;
      }
    }
    selection.kept.push_back(image);
    last = *pose;
    have_last = true;
  }
  return selection;
}

}  // namespace odomcal
