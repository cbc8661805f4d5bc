#include "odomcal/plugin/colmap/mapper_policy.h"

#include <stdexcept>

namespace odomcal {

void MapperPolicyOptions::Check() const {
  if (max_seeds < 1) {
    throw std::invalid_argument("mapper max_seeds must be >= 1, got " +
                                std::to_string(max_seeds));
  }
  if (max_matching_rounds < 1 || max_matching_rounds > 2) {
    throw std::invalid_argument(
        "mapper max_matching_rounds must be 1 or 2, got " +
        std::to_string(max_matching_rounds));
  }
}

MapperPolicy::MapperPolicy(const MapperPolicyOptions& options)
    : options_(options) {
  options_.Check();
}

MapperStep MapperPolicy::Next() const {
  MapperStep step;
  if (!round_over_) {
    step.kind = MapperStep::Kind::kMap;
    step.matching_round = round_;
    step.random_seed = static_cast<int>(attempts_.size() - round_begin_);
    return step;
  }
  const std::vector<MapperAttempt> round(attempts_.begin() + round_begin_,
                                         attempts_.end());
  if (round_ + 1 < options_.max_matching_rounds && ShouldMatchAgain(round)) {
    step.kind = MapperStep::Kind::kMatchAgain;
    step.matching_round = round_ + 1;
  }
  return step;
}

void MapperPolicy::Record(const MapperAttempt& attempt) {
  const MapperStep step = Next();
  if (step.kind != MapperStep::Kind::kMap ||
      attempt.matching_round != step.matching_round ||
      attempt.random_seed != step.random_seed) {
    throw std::logic_error(
        "MapperPolicy::Record: not the run Next() asked for");
  }
  attempts_.push_back(attempt);
  const MapperAttempt& last = attempts_.back();
  if (last.produced_model) {
    // Any earlier run, of this matching or an earlier one, that the last
    // one repeats: another seed would change nothing there.
    const bool accepted = OdometryAcceptsModel(last);
    for (size_t i = 0; i + 1 < attempts_.size(); ++i) {
      const MapperAttempt& other = attempts_[i];
      if (!accepted && !repeated_ &&
          (RepeatsContradictions(last, other) ||
           RepeatsUntestedPairs(last, other))) {
        repeated_ = other;
      }
    }
    round_over_ = accepted || repeated_.has_value();
  }
  if (attempts_.size() - round_begin_ >=
      static_cast<size_t>(options_.max_seeds)) {
    round_over_ = true;
  }
}

void MapperPolicy::MatchedAgain() {
  if (Next().kind != MapperStep::Kind::kMatchAgain) {
    throw std::logic_error("MapperPolicy::MatchedAgain: no matching was due");
  }
  ++round_;
  round_begin_ = attempts_.size();
  round_over_ = false;
  repeated_.reset();
}

bool MapperPolicy::LastAccepted() const {
  return !attempts_.empty() && OdometryAcceptsModel(attempts_.back());
}

int MapperPolicy::Best() const { return BestMapperAttempt(attempts_); }

std::optional<std::string> MapperPolicy::ContradictionWarning() const {
  const int chosen = Best();
  if (chosen < 0) return std::nullopt;
  const MapperAttempt& best = attempts_[chosen];
  if (OdometryAcceptsModel(best) || !best.pairs_tested ||
      attempts_.size() <= 1) {
    return std::nullopt;
  }
  const MapperAttempt& last = attempts_.back();
  if (repeated_) {
    const MapperAttempt& first = *repeated_;
    const std::string runs =
        first.matching_round == last.matching_round
            ? "COLMAP mapper runs with --random_seed " +
                  std::to_string(first.random_seed) + " and " +
                  std::to_string(last.random_seed) +
                  (last.matching_round == 0 ? "" : " on the new matches")
            : "COLMAP mapper runs on two matchings (" +
                  MapperAttemptName(first) + ", " + MapperAttemptName(last) +
                  ")";
    return runs + " gave the same " +
           std::to_string(last.num_contradicting_pairs) +
           " motion pairs that contradict the odometry: the odometry or the "
           "images "
           "disagree there, not COLMAP's randomness";
  }
  return "every one of " + std::to_string(attempts_.size()) +
         " COLMAP mapper runs" +
         (last.matching_round == 0 ? "" : " on two matchings") +
         " gave motion pairs that contradict the odometry; the model of " +
         MapperAttemptName(attempts_[chosen]) + " contradicts it least";
}

std::string MapperAttemptName(const MapperAttempt& attempt) {
  return "--random_seed " + std::to_string(attempt.random_seed) +
         (attempt.matching_round == 0 ? "" : " on the new matches");
}

}  // namespace odomcal
