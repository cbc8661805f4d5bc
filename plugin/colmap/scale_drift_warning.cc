#include "odomcal/plugin/colmap/scale_drift_warning.h"

#include "odomcal/adapters/timestamp.h"

#include <cmath>
#include <cstdio>

namespace odomcal {

std::string SignedPercent(double fraction) {
  char text[32];
  std::snprintf(text, sizeof(text), "%+.1f %%", 100.0 * fraction);
  return text;
}

std::string ScaleDriftWarning(const std::string& sub_model,
                              const ScaleDrift& drift,
                              const CalibrationResult& result) {
  const std::string span = FormatTimestampSeconds(drift.first_stamp_ns) +
                           " to " +
                           FormatTimestampSeconds(drift.last_stamp_ns) + " s";
  std::string text = "sub-model " + sub_model + ": COLMAP's scale ";
  if (drift.trend_measured) {
    char sigma[32];
    std::snprintf(
        sigma, sizeof(sigma), "%.1f %%", 300.0 * drift.relative_drift_stddev);
    text += "drifts by " + SignedPercent(drift.relative_drift) + " (3 sigma " +
            sigma + ") from " + span +
            " (seen in the step lengths against the odometry)";
  } else {
    text += "changes from " + span +
            " (seen in the step lengths against the odometry; too few motion "
            "pairs to measure its trend)";
  }
  text += result.has_estimate && result.observability.ExtrinsicDetermined()
              ? ": calibrated and exported as "
              : ": calibrated (nothing exported: the "
                "extrinsic is not determined) as ";
  text += std::to_string(drift.stretches.size()) +
          " stretches with scales of their own:";
  for (size_t k = 0; k < drift.stretches.size(); ++k) {
    const ScaleStretch& stretch = drift.stretches[k];
    const double value = result.metric_scales.at(stretch.output_segment);
    char scale[32];
    std::snprintf(scale, sizeof(scale), "%.5g m/unit", value);
    const bool determined =
        std::isfinite(value) &&
        result.observability.metric_scales.at(stretch.output_segment) ==
            Determination::kEstimated;
    text += std::string(k == 0 ? " " : ", ") +
            FormatTimestampSeconds(stretch.first_stamp_ns) + " .. " +
            FormatTimestampSeconds(stretch.last_stamp_ns) + " s " +
            (determined ? std::string(scale) : "scale undetermined");
  }
  return text;
}

}  // namespace odomcal
