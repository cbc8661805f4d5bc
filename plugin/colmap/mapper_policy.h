// The mapper-attempt and rematch policy of `odomcal run` as one object: it
// says which COLMAP run comes next given the runs so far, and which model to
// keep. The decisions are the pure functions of mapper_attempts.h; this
// object only keeps the state between them (the matching round, the seed,
// the run an attempt repeated).
//
// Usage: while Next() is not kDone, run what it says (map with its seed on
// its matching, or match again), then Record() the mapper run or call
// MatchedAgain(); finally Best() and ContradictionWarning().
#pragma once

#include "odomcal/plugin/colmap/mapper_attempts.h"

#include <optional>
#include <string>
#include <vector>

namespace odomcal {

struct MapperPolicyOptions {
  // COLMAP mapper runs (--random_seed 0, 1, ...) per matching at most
  // (`odomcal run --mapper_attempts`).
  int max_seeds = 3;
  // Matchings of the images at most, 1 or 2: 2 matches again once when the
  // seeds do not help (ShouldMatchAgain); 1 never does (`--rematch off`).
  int max_matching_rounds = 2;

  // Throws std::invalid_argument naming the bad field.
  void Check() const;
};

struct MapperStep {
  enum class Kind {
    kMap,         // run the mapper with `random_seed` on `matching_round`
    kMatchAgain,  // match the images anew for `matching_round`
    kDone,        // keep Best()
  };
  Kind kind = Kind::kDone;
  int matching_round = 0;
  int random_seed = 0;
};

class MapperPolicy {
 public:
  // Throws std::invalid_argument for bad options.
  explicit MapperPolicy(const MapperPolicyOptions& options);

  // What to run next, given the attempts recorded so far.
  MapperStep Next() const;

  // The mapper run Next() asked for: its matching_round and random_seed
  // must be Next()'s (std::logic_error otherwise).
  void Record(const MapperAttempt& attempt);

  // The matching Next() asked for is done.
  void MatchedAgain();

  const std::vector<MapperAttempt>& attempts() const { return attempts_; }

  // Whether the odometry accepts the last recorded attempt's model.
  bool LastAccepted() const;

  // The earlier attempt whose contradictions (or untested pairs) the last
  // recorded one of this matching repeats, if any: further seeds would not
  // help.
  const std::optional<MapperAttempt>& repeated() const { return repeated_; }

  // Index in attempts() of the model to keep, -1 when none produced one.
  int Best() const;

  // Why the kept model still has motion pairs the odometry contradicts,
  // when it has and more than one run was made; else nothing. (A refusal for
  // too little motion explains itself in the calibration's status.)
  std::optional<std::string> ContradictionWarning() const;

 private:
  MapperPolicyOptions options_;
  std::vector<MapperAttempt> attempts_;
  int round_ = 0;           // the current matching
  size_t round_begin_ = 0;  // its first attempt in attempts_
  bool round_over_ = false;
  std::optional<MapperAttempt> repeated_;  // in the current matching
};

// "--random_seed 2", "--random_seed 0 on the new matches".
std::string MapperAttemptName(const MapperAttempt& attempt);

}  // namespace odomcal
