#include "odomcal/adapters/frame_selection.h"

#include "odomcal/adapters/association.h"
#include "odomcal/solver/angles.h"
#include "odomcal/solver/format_number.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace odomcal {

void FrameSelectionOptions::Check() const {
  // The message starts with the field's name, like the other options' Check().
  const auto check = [](double value, bool zero_allowed, const char* name) {
    if (!std::isfinite(value) || value < 0.0 ||
        (!zero_allowed && value == 0.0)) {
      throw std::invalid_argument(std::string(name) + " must be finite and " +
                                  (zero_allowed ? ">= 0" : "> 0") + ", got " +
                                  FormatNumber(value));
    }
  };
  if (min_translation_m != kAutomaticFrameSpacing) {
    check(min_translation_m, true, "min_translation_m");
  }
  if (min_rotation_deg != kAutomaticFrameSpacing) {
    check(min_rotation_deg, true, "min_rotation_deg");
  }
  if (!(field_of_view_deg > 0.0 && field_of_view_deg < 180.0)) {
    throw std::invalid_argument("field_of_view_deg must be in (0, 180), got " +
                                FormatNumber(field_of_view_deg));
  }
  if (max_odometry_gap_s != kAutomaticOdometryGap) {
    check(max_odometry_gap_s, false, "max_odometry_gap_s");
  }
}

FrameSpacing AutomaticFrameSpacing(double field_of_view_deg) {
  FrameSpacing spacing;
  spacing.min_rotation_deg = field_of_view_deg / 8.0;
  spacing.min_translation_m =
      kTypicalSceneDepthM * std::tan(field_of_view_deg / 16.0 * kDegToRad);
  return spacing;
}

double FieldOfViewDeg(double focal_px, double principal_point_px) {
  return 2.0 * std::atan(principal_point_px / focal_px) * kRadToDeg;
}

FrameSpacing ResolvedFrameSpacing(const FrameSelectionOptions& options) {
  FrameSpacing spacing = AutomaticFrameSpacing(options.field_of_view_deg);
  if (options.min_translation_m != kAutomaticFrameSpacing) {
    spacing.min_translation_m = options.min_translation_m;
  }
  if (options.min_rotation_deg != kAutomaticFrameSpacing) {
    spacing.min_rotation_deg = options.min_rotation_deg;
  }
  return spacing;
}

FrameSelection SelectFrames(std::vector<TimedImage> images,
                            const Trajectory& odometry,
                            const FrameSelectionOptions& options) {
  options.Check();
  std::stable_sort(images.begin(),
                   images.end(),
                   [](const TimedImage& a, const TimedImage& b) {
                     return a.stamp_ns < b.stamp_ns;
                   });
  const double max_gap_s =
      OdometryGapLimitS(options.max_odometry_gap_s, odometry);
  FrameSelection selection;
  selection.spacing = ResolvedFrameSpacing(options);
  selection.num_images = static_cast<int>(images.size());
  bool have_last = false;
  Rigid3d last;
  for (const TimedImage& image : images) {
    InterpolationFailure why;
    const auto pose =
        InterpolateOdometry(odometry,
                            image.stamp_ns + options.camera_time_offset_ns,
                            max_gap_s,
                            &why);
    if (!pose) {
      ++selection.num_outside_odometry;
      continue;
    }
    if (have_last) {
      const Rigid3d motion = Inverse(last) * *pose;
      if (motion.translation.norm() < selection.spacing.min_translation_m &&
          RotationAngle(motion.rotation) <
              selection.spacing.min_rotation_deg * kDegToRad) {
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
