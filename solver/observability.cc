#include "odomcal/solver/observability.h"

#include <utility>

namespace odomcal {
namespace {

std::vector<std::pair<std::string, Determination>> Named(
    const Observability& o) {
  std::vector<std::pair<std::string, Determination>> named = {
      {"rotation", o.rotation},
      {"translation_x", o.translation_x},
      {"translation_y", o.translation_y},
      {"translation_z", o.translation_z}};
  for (size_t k = 0; k < o.metric_scales.size(); ++k) {
    named.emplace_back(ScaleName(k, o.metric_scales.size()),
                       o.metric_scales[k]);
  }
  return named;
}

std::vector<std::string> NamesWith(const Observability& o,
                                   Determination determination) {
  std::vector<std::string> names;
  for (const auto& [name, d] : Named(o)) {
    if (d == determination) names.push_back(name);
  }
  return names;
}

}  // namespace

std::string ToString(TranslationZSource source) {
  switch (source) {
    case TranslationZSource::kGiven:
      return "given";
    case TranslationZSource::kMotion:
      return "motion";
    case TranslationZSource::kFloorPlane:
      return "floor_plane";
  }
  return "given";
}

bool Observability::ExtrinsicDetermined() const {
  return rotation == Determination::kEstimated &&
         translation_x == Determination::kEstimated &&
         translation_y == Determination::kEstimated &&
         translation_z != Determination::kUndetermined;
}

bool Observability::ScaleDetermined(size_t segment) const {
  return segment < metric_scales.size() &&
         metric_scales[segment] == Determination::kEstimated;
}

bool Observability::AllDetermined() const {
  for (size_t k = 0; k < metric_scales.size(); ++k) {
    if (!ScaleDetermined(k)) return false;
  }
  return ExtrinsicDetermined();
}

Observability Observability::Nothing(int num_segments) {
  Observability nothing;
  nothing.rotation = Determination::kUndetermined;
  nothing.translation_x = Determination::kUndetermined;
  nothing.translation_y = Determination::kUndetermined;
  nothing.translation_z = Determination::kUndetermined;
  nothing.metric_scales.assign(num_segments, Determination::kUndetermined);
  return nothing;
}

std::string ScaleName(size_t segment, size_t num_segments) {
  return num_segments == 1 ? "metric_scale"
                           : "metric_scale[" + std::to_string(segment) + "]";
}

std::vector<std::string> UnobservableNames(const Observability& o) {
  std::vector<std::string> names = NamesWith(o, Determination::kHeld);
  for (std::string& name : NamesWith(o, Determination::kUndetermined)) {
    names.push_back(std::move(name));
  }
  return names;
}

std::vector<std::string> UndeterminedNames(const Observability& o) {
  return NamesWith(o, Determination::kUndetermined);
}

}  // namespace odomcal
