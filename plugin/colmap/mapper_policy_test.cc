#include "odomcal/plugin/colmap/mapper_policy.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace odomcal {
namespace {

// Attempts as SummarizeMapperAttempt would give them, built by hand: the
// policy reads only these fields.
MapperAttempt Clean(int round, int seed) {
  MapperAttempt attempt;
  attempt.matching_round = round;
  attempt.random_seed = seed;
  attempt.produced_model = true;
  attempt.status = CalibrationStatus::kSuccess;
  attempt.pairs_tested = true;
  attempt.num_pairs = 40;
  attempt.num_pairs_used = 40;
  return attempt;
}

// Contradicted at the pairs starting at `first_stamp_ns` (one per entry).
MapperAttempt Contradicted(int round,
                           int seed,
                           const std::vector<int64_t>& first_stamps_ns) {
  MapperAttempt attempt = Clean(round, seed);
  for (const int64_t stamp : first_stamps_ns) {
    attempt.contradicted_spans.push_back({stamp, stamp + 100});
  }
  attempt.num_contradicting_pairs = static_cast<int>(first_stamps_ns.size());
  attempt.num_pairs_used = 40 - attempt.num_contradicting_pairs;
  return attempt;
}

MapperAttempt NoModel(int round, int seed) {
  MapperAttempt attempt;
  attempt.matching_round = round;
  attempt.random_seed = seed;
  return attempt;
}

void ExpectMap(const MapperPolicy& policy, int round, int seed) {
  const MapperStep step = policy.Next();
  EXPECT_EQ(step.kind, MapperStep::Kind::kMap);
  EXPECT_EQ(step.matching_round, round);
  EXPECT_EQ(step.random_seed, seed);
}

TEST(MapperPolicy, StopsAtTheFirstModelTheOdometryAccepts) {
  MapperPolicy policy(MapperPolicyOptions{});
  ExpectMap(policy, 0, 0);
  policy.Record(Clean(0, 0));
  EXPECT_TRUE(policy.LastAccepted());
  EXPECT_EQ(policy.Next().kind, MapperStep::Kind::kDone);
  EXPECT_EQ(policy.Best(), 0);
  EXPECT_FALSE(policy.ContradictionWarning());
}

TEST(MapperPolicy, MapsAgainWithTheNextSeedWhileContradicted) {
  MapperPolicy policy(MapperPolicyOptions{});
  policy.Record(Contradicted(0, 0, {10, 20}));
  EXPECT_FALSE(policy.LastAccepted());
  ExpectMap(policy, 0, 1);
  policy.Record(NoModel(0, 1));  // no model: nothing to compare, next seed
  ExpectMap(policy, 0, 2);
  policy.Record(Clean(0, 2));
  EXPECT_EQ(policy.Next().kind, MapperStep::Kind::kDone);
  EXPECT_EQ(policy.Best(), 2);
  EXPECT_FALSE(policy.ContradictionWarning());
}

TEST(MapperPolicy, StopsSeedsThatRepeatTheContradictionsAndMatchesAgain) {
  MapperPolicy policy(MapperPolicyOptions{});
  policy.Record(Contradicted(0, 0, {10, 20}));
  policy.Record(Contradicted(0, 1, {10, 20}));
  ASSERT_TRUE(policy.repeated());
  EXPECT_EQ(policy.repeated()->random_seed, 0);
  // Seed 2 would change nothing: the matches are tried anew instead.
  const MapperStep step = policy.Next();
  EXPECT_EQ(step.kind, MapperStep::Kind::kMatchAgain);
  EXPECT_EQ(step.matching_round, 1);
  EXPECT_THROW(policy.Record(Clean(0, 2)), std::logic_error);
  policy.MatchedAgain();
  EXPECT_FALSE(policy.repeated());
  ExpectMap(policy, 1, 0);
  // The new matches repeat the first matching's contradictions: the
  // odometry or the images disagree there; nothing more to try.
  policy.Record(Contradicted(1, 0, {10, 20}));
  EXPECT_EQ(policy.Next().kind, MapperStep::Kind::kDone);
  EXPECT_EQ(policy.attempts().size(), 3u);
  EXPECT_EQ(policy.Best(), 0);  // the earliest of equals
  EXPECT_EQ(policy.ContradictionWarning().value_or(""),
            "COLMAP mapper runs on two matchings (--random_seed 0, "
            "--random_seed 0 on the new matches) gave the same 2 motion pairs "
            "that contradict the odometry: the odometry or the images "
            "disagree there, not COLMAP's randomness");
}

TEST(MapperPolicy, KeepsTheLeastContradictedModelAfterAllSeeds) {
  MapperPolicyOptions options;
  options.max_seeds = 2;
  options.max_matching_rounds = 1;  // --rematch off
  MapperPolicy policy(options);
  policy.Record(Contradicted(0, 0, {10, 20, 30}));
  ExpectMap(policy, 0, 1);
  policy.Record(Contradicted(0, 1, {40}));
  EXPECT_FALSE(policy.repeated());
  EXPECT_EQ(policy.Next().kind, MapperStep::Kind::kDone);
  EXPECT_EQ(policy.Best(), 1);
  EXPECT_EQ(policy.ContradictionWarning().value_or(""),
            "every one of 2 COLMAP mapper runs gave motion pairs that "
            "contradict the odometry; the model of --random_seed 1 "
            "contradicts it least");
}

TEST(MapperPolicy, MatchesAgainAfterSeedsWithoutAnAcceptedModel) {
  MapperPolicyOptions options;
  options.max_seeds = 2;
  MapperPolicy policy(options);
  policy.Record(Contradicted(0, 0, {10}));
  policy.Record(Contradicted(0, 1, {20}));
  ASSERT_EQ(policy.Next().kind, MapperStep::Kind::kMatchAgain);
  policy.MatchedAgain();
  policy.Record(Clean(1, 0));
  EXPECT_EQ(policy.Next().kind, MapperStep::Kind::kDone);
  EXPECT_EQ(policy.Best(), 2);
  EXPECT_FALSE(policy.ContradictionWarning());
}

TEST(MapperPolicy, NeitherRemapsNorRematchesWhenNoRunMadeAModel) {
  MapperPolicyOptions options;
  options.max_seeds = 2;
  MapperPolicy policy(options);
  policy.Record(NoModel(0, 0));
  policy.Record(NoModel(0, 1));
  // New matches help a model the odometry contradicts, not a failed mapper.
  EXPECT_EQ(policy.Next().kind, MapperStep::Kind::kDone);
  EXPECT_EQ(policy.Best(), -1);
  EXPECT_FALSE(policy.ContradictionWarning());
}

TEST(MapperPolicy, StopsSeedsThatRepeatTheSameUntestedPairs) {
  MapperPolicy policy(MapperPolicyOptions{});
  MapperAttempt straight = Clean(0, 0);
  straight.status = CalibrationStatus::kNotEnoughMotion;
  straight.pairs_tested = false;
  straight.pair_spans = {{0, 100}, {100, 200}};
  policy.Record(straight);
  ExpectMap(policy, 0, 1);
  straight.random_seed = 1;
  policy.Record(straight);
  ASSERT_TRUE(policy.repeated());
  // A refusal for too little motion explains itself: no warning.
  EXPECT_FALSE(policy.ContradictionWarning());
}

TEST(MapperPolicy, RefusesBadOptions) {
  MapperPolicyOptions options;
  options.max_seeds = 0;
  EXPECT_THROW(MapperPolicy{options}, std::invalid_argument);
  options.max_seeds = 1;
  options.max_matching_rounds = 3;
  EXPECT_THROW(MapperPolicy{options}, std::invalid_argument);
}

}  // namespace
}  // namespace odomcal
