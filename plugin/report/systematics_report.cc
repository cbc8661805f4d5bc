#include "odomcal/plugin/report/systematics_report.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/solver/format_number.h"

#include <cmath>
#include <cstdio>

namespace odomcal {
namespace {

using nlohmann::json;

const char* const kIntrinsicNames[3] = {
    "yaw_scale", "yaw_per_metre_rad", "yaw_rate_bias_rad_s"};

double Value(const OdometryIntrinsics& intrinsics, int k) {
  return k == 0 ? intrinsics.yaw_scale
                : (k == 1 ? intrinsics.yaw_per_metre_rad
                          : intrinsics.yaw_rate_bias_rad_s);
}

}  // namespace

void AddSystematicsJson(const SystematicsEstimate& estimate, json* out) {
  (*out)["camera_time_offset_s"] = NsToSeconds(estimate.camera_time_offset_ns);
  json intrinsics = {
      {"estimated",
       estimate.intrinsics_estimated[0] || estimate.intrinsics_estimated[1] ||
           estimate.intrinsics_estimated[2]},
      {"distance_scale", 1.0},
      {"held", estimate.intrinsics_reasons},
  };
  for (int k = 0; k < 3; ++k) {
    intrinsics[kIntrinsicNames[k]] = Value(estimate.intrinsics, k);
  }
  if (estimate.right_over_left) {
    intrinsics["right_over_left"] = *estimate.right_over_left;
  }
  (*out)["odometry_intrinsics"] = intrinsics;
  if ((*out)["stddev"].is_object()) {
    json& stddev = (*out)["stddev"];
    stddev["camera_time_offset_s"] =
        estimate.time_offset_estimated
            ? json(estimate.camera_time_offset_stddev_s)
            : json(nullptr);
    for (int k = 0; k < 3; ++k) {
      stddev[kIntrinsicNames[k]] = estimate.intrinsics_estimated[k]
                                       ? json(estimate.intrinsics_stddev[k])
                                       : json(nullptr);
    }
    if (estimate.right_over_left) {
      stddev["right_over_left"] = estimate.right_over_left_stddev;
    }
  }
  json time_offset = {
      {"estimated", estimate.time_offset_estimated},
      {"reason", estimate.time_offset_reason},
      {"num_rounds", estimate.num_rounds},
      {"search_ran", estimate.coarse_search_ran},
  };
  if (estimate.coarse_search_ran) {
    time_offset["search_range_s"] = estimate.search_range_s;
    time_offset["search_step_s"] = estimate.coarse.step_s;
    time_offset["coarse_resolved"] = estimate.coarse.resolved;
    time_offset["coarse_peak_s"] = NsToSeconds(estimate.coarse.peak_ns);
    time_offset["coarse_peak_correlation"] = estimate.coarse.peak_correlation;
    time_offset["coarse_peak_half_width_s"] = estimate.coarse.peak_half_width_s;
    time_offset["coarse_num_intervals"] = estimate.coarse.num_intervals;
  }
  (*out)["diagnostics"]["time_offset"] = time_offset;
}

std::string SystematicsSummary(const SystematicsEstimate& estimate) {
  std::string out =
      "  clock offset: odometry_time = camera_time + " +
      FormatPrintf("%.4f s", NsToSeconds(estimate.camera_time_offset_ns));
  if (estimate.time_offset_estimated) {
    out += FormatPrintf("  +- %.2f ms (3 sigma), estimated",
                        3e3 * estimate.camera_time_offset_stddev_s);
    if (estimate.coarse_search_ran) {
      out += FormatPrintf(" (coarse peak %.3f s)",
                          NsToSeconds(estimate.coarse.peak_ns));
    }
  } else {
    out += ", given (" + estimate.time_offset_reason + ")";
  }
  out += "\n  odometry intrinsics:";
  const char* formats[3] = {" yaw_scale %.5f",
                            " yaw_per_metre %.5f rad/m",
                            " yaw_rate_bias %.6f rad/s"};
  const char* sigma_formats[3] = {
      " +- %.5f", " +- %.5f rad/m", " +- %.6f rad/s"};
  for (int k = 0; k < 3; ++k) {
    out += FormatPrintf(formats[k], Value(estimate.intrinsics, k));
    out += estimate.intrinsics_estimated[k]
               ? FormatPrintf(sigma_formats[k],
                              3.0 * estimate.intrinsics_stddev[k])
               : std::string(" (held)");
    out += k < 2 ? "," : "";
  }
  out += " (3 sigma; distance scale 1: not separable from the metric scale)\n";
  if (estimate.right_over_left) {
    out += FormatPrintf("  wheels: right / left radius %.5f",
                        *estimate.right_over_left) +
           FormatPrintf(" +- %.5f (3 sigma)\n",
                        3.0 * estimate.right_over_left_stddev);
  }
  return out;
}

}  // namespace odomcal
