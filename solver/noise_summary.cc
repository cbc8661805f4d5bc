// NoiseSummary: the estimated noise as one line of text.

#include "odomcal/solver/noise_estimation.h"
#include "odomcal/solver/noise_estimation_internal.h"

#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

using internal::Index;

std::string Ratio(double value) {
  std::ostringstream text;
  text.precision(2);
  text << value;
  return text.str();
}

}  // namespace

std::string ToString(NoiseBound bound) {
  switch (bound) {
    case NoiseBound::kNone:
      return "none";
    case NoiseBound::kFloor:
      return "floor";
    case NoiseBound::kCeiling:
      return "ceiling";
  }
  return "none";
}

std::string NoiseSummary(const NoiseEstimate& estimate) {
  std::ostringstream text;
  text << "noise estimated from " << estimate.num_pairs
       << " pairs (standard deviations relative to the given noise): ";
  bool first = true;
  std::vector<std::string> kept, floor, ceiling;
  for (int c = 0; c < kNumNoiseComponents; ++c) {
    if (!estimate.component_present[c]) continue;
    if (estimate.component_bound[c] == NoiseBound::kFloor) {
      floor.push_back(ToString(static_cast<NoiseComponent>(c)));
    }
    if (estimate.component_bound[c] == NoiseBound::kCeiling) {
      ceiling.push_back(ToString(static_cast<NoiseComponent>(c)));
      continue;
    }
    if (!estimate.component_estimated[c]) {
      if (c != Index(NoiseComponent::kOdometryTilt)) {
        kept.push_back(ToString(static_cast<NoiseComponent>(c)));
      }
      continue;
    }
    if (estimate.component_tie[c] != c) continue;  // with its representative
    std::vector<std::string> members;
    for (int d = 0; d < kNumNoiseComponents; ++d) {
      if (estimate.component_estimated[d] && estimate.component_tie[d] == c) {
        members.push_back(ToString(static_cast<NoiseComponent>(d)));
      }
    }
    text << (first ? "" : ", ") << members[0];
    for (size_t k = 1; k < members.size(); ++k) {
      text << (k + 1 == members.size() ? " and " : ", ") << members[k];
    }
    if (members.size() > 1) text << " (tied: not separable)";
    text << " x" << Ratio(estimate.SigmaRatio(static_cast<NoiseComponent>(c)));
    first = false;
  }
  if (first) text << "none determined";
  if (!kept.empty()) {
    text << "; kept as given: ";
    for (size_t k = 0; k < kept.size(); ++k) {
      text << (k == 0 ? "" : ", ") << kept[k];
    }
    text << " (not determined by these pairs)";
  }
  const auto list = [&](const std::vector<std::string>& names) {
    for (size_t k = 0; k < names.size(); ++k) {
      text << (k == 0 ? "" : ", ") << names[k];
    }
  };
  if (!ceiling.empty()) {
    text << "; kept as given, the data ask for over "
         << Ratio(kNoiseSigmaRatioCeiling) << "x: ";
    list(ceiling);
    text << " (an error the noise model does not describe, e.g. a "
            "systematic one)";
  }
  if (!floor.empty()) {
    text << "; held at " << Ratio(kNoiseSigmaRatioFloor)
         << "x, the data ask for less: ";
    list(floor);
  }
  if (estimate.misfit_widening >= 1.005) {
    text << "; standard deviations widened x" << Ratio(estimate.misfit_widening)
         << " for the misfit";
  }
  if (estimate.stddev_widening >= 1.005) {
    std::ostringstream percent;
    percent.setf(std::ios::fixed);
    percent.precision(1);
    percent << 100.0 * (estimate.stddev_widening - 1.0);
    text << "; standard deviations widened by up to " << percent.str()
         << " % for this estimate's own uncertainty (Kenward-Roger)";
  }
  return text.str();
}

}  // namespace odomcal
