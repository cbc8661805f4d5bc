#include "odomcal/plugin/colmap/image_coverage.h"

#include "odomcal/adapters/timestamp.h"
#include "odomcal/plugin/colmap/colmap_calibration.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

namespace odomcal {
namespace {

int Percent(double fraction) {
  return static_cast<int>(std::floor(100.0 * fraction + 0.5));
}

std::string Seconds(int64_t ns) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.1f", NsToSeconds(ns));
  return text;
}

}  // namespace

double CoverageStretch::Fraction() const {
  return num_images > 0 ? static_cast<double>(num_in_calibration) / num_images
                        : 0.0;
}

double ImageCoverage::Fraction() const {
  return num_selected_images > 0
             ? static_cast<double>(num_in_calibration) / num_selected_images
             : 0.0;
}

ImageCoverage SummarizeImageCoverage(
    const std::vector<TimedImage>& selected,
    const std::set<std::string>& registered,
    const std::set<std::string>& in_calibration,
    int min_gap_images) {
  ImageCoverage coverage;
  const int n = static_cast<int>(selected.size());
  coverage.num_selected_images = n;
  std::vector<bool> in(n), gap(n, false);
  for (int i = 0; i < n; ++i) {
    in[i] = in_calibration.count(selected[i].name) > 0;
    coverage.num_in_calibration += in[i] ? 1 : 0;
    coverage.num_registered_images +=
        registered.count(selected[i].name) > 0 ? 1 : 0;
  }
  // A missing run is a gap when it is long, or when nothing is covered.
  for (int i = 0; i < n;) {
    if (in[i]) {
      ++i;
      continue;
    }
    int end = i;
    while (end < n && !in[end]) ++end;
    if (end - i >= min_gap_images || coverage.num_in_calibration == 0) {
      std::fill(gap.begin() + i, gap.begin() + end, true);
    }
    i = end;
  }
  int64_t covered_ns = 0;
  for (int i = 0; i < n;) {
    int end = i;
    while (end < n && gap[end] == gap[i]) ++end;
    CoverageStretch stretch;
    stretch.in_calibration = !gap[i];
    stretch.first_image = i;
    stretch.last_image = end - 1;
    stretch.first_stamp_ns = selected[i].stamp_ns;
    stretch.last_stamp_ns = selected[end - 1].stamp_ns;
    stretch.num_images = end - i;
    int first_in = -1, last_in = -1;
    for (int k = i; k < end; ++k) {
      stretch.num_registered += registered.count(selected[k].name) > 0 ? 1 : 0;
      if (in[k]) {
        ++stretch.num_in_calibration;
        if (first_in < 0) first_in = k;
        last_in = k;
      }
    }
    if (first_in >= 0) {
      covered_ns += selected[last_in].stamp_ns - selected[first_in].stamp_ns;
    }
    coverage.stretches.push_back(stretch);
    i = end;
  }
  const int64_t span_ns =
      n > 1 ? selected[n - 1].stamp_ns - selected[0].stamp_ns : 0;
  coverage.duration_fraction =
      span_ns > 0 ? static_cast<double>(covered_ns) / span_ns
                  : (coverage.num_in_calibration == n && n > 0 ? 1.0 : 0.0);
  return coverage;
}

std::set<std::string> RegisteredImages(const ColmapCalibrationRun& run) {
  std::set<std::string> names;
  for (const ColmapSegment& segment : run.segments) {
    names.insert(segment.image_names.begin(), segment.image_names.end());
  }
  return names;
}

std::set<std::string> ImagesInCalibration(const ColmapCalibrationRun& run,
                                          int64_t camera_time_offset_ns) {
  // Per input segment, the odometry-time spans of the pairs calibrated that
  // the odometry does not contradict.
  std::vector<std::vector<std::pair<int64_t, int64_t>>> spans(
      run.segments.size());
  const auto& input_of = run.check.input_segment_of_output_segment;
  const std::vector<char>& contradicts = run.check.contradicts_odometry;
  for (size_t p = 0; p < run.check.pairs.size(); ++p) {
    const MotionPair& pair = run.check.pairs[p];
    if (p < contradicts.size() && contradicts[p] != 0) continue;
    if (pair.segment < 0 || pair.segment >= static_cast<int>(input_of.size()))
      continue;
    const int input = input_of[pair.segment];
    if (input < 0 || input >= static_cast<int>(spans.size())) continue;
    spans[input].emplace_back(pair.stamp_i_ns, pair.stamp_j_ns);
  }
  std::set<std::string> names;
  for (size_t s = 0; s < run.segments.size(); ++s) {
    const ColmapSegment& segment = run.segments[s];
    for (size_t k = 0; k < segment.image_names.size(); ++k) {
      const int64_t t =
          segment.trajectory.poses[k].stamp_ns + camera_time_offset_ns;
      const bool inside =
          std::any_of(spans[s].begin(), spans[s].end(), [t](const auto& span) {
            return span.first <= t && t <= span.second;
          });
      if (inside) names.insert(segment.image_names[k]);
    }
  }
  return names;
}

std::string CoverageClause(const ImageCoverage& coverage) {
  return std::to_string(coverage.num_in_calibration) + " of " +
         std::to_string(coverage.num_selected_images) + " selected images (" +
         std::to_string(Percent(coverage.Fraction())) +
         " %) in the calibration";
}

std::optional<std::string> CoverageWarning(const ImageCoverage& coverage,
                                           double min_fraction) {
  if (coverage.num_selected_images == 0 ||
      coverage.Fraction() >= min_fraction) {
    return std::nullopt;
  }
  std::string gaps;
  int num_gaps = 0;
  const int64_t start_ns = coverage.stretches.empty()
                               ? 0
                               : coverage.stretches.front().first_stamp_ns;
  for (const CoverageStretch& stretch : coverage.stretches) {
    if (stretch.in_calibration) continue;
    if (++num_gaps > 3) continue;
    gaps += std::string(gaps.empty() ? "" : ", ") + "images " +
            std::to_string(stretch.first_image + 1) + "-" +
            std::to_string(stretch.last_image + 1) + " (" +
            Seconds(stretch.first_stamp_ns - start_ns) + "-" +
            Seconds(stretch.last_stamp_ns - start_ns) + " s, " +
            std::to_string(stretch.num_registered) + " registered)";
  }
  if (num_gaps > 3) gaps += " and " + std::to_string(num_gaps - 3) + " more";
  return "only " + CoverageClause(coverage) + " (below " +
         std::to_string(Percent(min_fraction)) + " %), covering " +
         std::to_string(Percent(coverage.duration_fraction)) +
         " % of the drive's duration: the calibration and the metric model "
         "describe part of the drive" +
         (gaps.empty() ? std::string() : "; not in it: " + gaps);
}

}  // namespace odomcal
