#include "odomcal/plugin/colmap/colmap_runner.h"

#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream buffer;
  buffer << file.rdbuf();
  return buffer.str();
}

// dir/fake_colmap: prints COLMAP `version`'s banner for `help`, otherwise
// runs `body` (sh); its path.
std::string WriteFakeColmapScript(const fs::path& dir,
                                  const std::string& body,
                                  const std::string& version = "3.8") {
  const std::string fake = (dir / "fake_colmap").string();
  std::ofstream script(fake);
  script << "#!/bin/sh\n"
         << "if [ \"$1\" = help ]; then echo 'COLMAP " << version
         << " -- Structure-from-Motion and Multi-View Stereo'; exit 0; fi\n"
         << body;
  script.close();
  ::chmod(fake.c_str(), 0755);
  return fake;
}

// A stand-in for the colmap program: prints a version banner for `help`,
// records its arguments one per line, and exits with $FAKE_EXIT.
class ColmapRunnerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("runner_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "ws");
    WriteFake("3.8", 0);
  }
  void TearDown() override { fs::remove_all(dir_); }

  void WriteFake(const std::string& version, int exit_code) {
    fake_ = WriteFakeColmapScript(
        dir_,
        "for a in \"$@\"; do echo \"$a\" >> " + (dir_ / "args.txt").string() +
            "; done\n"
            "echo \"glog_to_stderr=$GLOG_logtostderr\"\n"
            "echo 'Check failed: something' >&2\n"
            "exit " +
            std::to_string(exit_code) + "\n",
        version);
  }

  ColmapRunner Runner() const {
    ColmapRunner::Options options;
    options.executable = fake_;
    options.workspace = (dir_ / "ws").string();
    return ColmapRunner(options);
  }

  fs::path dir_;
  std::string fake_;
};

TEST(ParseColmapVersion, ReadsTheBannerOfEveryRelease) {
  const ColmapVersion v38 = ParseColmapVersion(
      "COLMAP 3.8 -- Structure-from-Motion and Multi-View Stereo");
  EXPECT_EQ(v38.major, 3);
  EXPECT_EQ(v38.minor, 8);
  // The 3.10 release calls itself 3.10-dev.
  const ColmapVersion v310 = ParseColmapVersion(
      "COLMAP 3.10-dev -- Structure-from-Motion and Multi-View Stereo");
  EXPECT_EQ(v310.minor, 10);
  const ColmapVersion v313 = ParseColmapVersion("COLMAP 3.13.0 (Commit abc)");
  EXPECT_EQ(v313.patch, 0);
  // 4.1 prints one line, without "-- Structure-from-Motion ...".
  const ColmapVersion v411 = ParseColmapVersion(
      "COLMAP 4.1.1 (Commit 1a2b3c4 on 2026-07-17 with CUDA)");
  EXPECT_EQ(v411.major, 4);
  EXPECT_EQ(v411.minor, 1);
  EXPECT_EQ(v411.patch, 1);
  EXPECT_THROW(ParseColmapVersion("usage: something else"), ColmapError);
}

// The names COLMAP's sources register at each release tag.
TEST(ColmapOptionNames, FollowTheRenamesOf3Point13) {
  const ColmapOptionNames v38 =
      ColmapOptionNamesFor(ParseColmapVersion("COLMAP 3.8 -- SfM"));
  EXPECT_EQ(v38.extraction_use_gpu, "SiftExtraction.use_gpu");
  EXPECT_EQ(v38.extraction_num_threads, "SiftExtraction.num_threads");
  EXPECT_EQ(v38.extraction_max_num_features, "SiftExtraction.max_num_features");
  EXPECT_EQ(v38.matching_use_gpu, "SiftMatching.use_gpu");
  EXPECT_EQ(v38.mapper_image_list_path, "image_list_path");
  EXPECT_EQ(v38.mapper_random_seed, std::vector<std::string>{"random_seed"});
  const ColmapOptionNames v312 =
      ColmapOptionNamesFor(ParseColmapVersion("COLMAP 3.12.6 -- SfM"));
  EXPECT_EQ(v312.extraction_use_gpu, "SiftExtraction.use_gpu");
  EXPECT_EQ(v312.mapper_image_list_path, "image_list_path");
  for (const char* banner : {"COLMAP 3.13.0 -- SfM",
                             "COLMAP 4.0.4 -- SfM",
                             "COLMAP 4.1.1 (Commit abc on 2026-07-17)"}) {
    const ColmapOptionNames names =
        ColmapOptionNamesFor(ParseColmapVersion(banner));
    EXPECT_EQ(names.extraction_use_gpu, "FeatureExtraction.use_gpu") << banner;
    EXPECT_EQ(names.extraction_num_threads, "FeatureExtraction.num_threads");
    // The SIFT options keep their prefix: FeatureExtraction.max_num_features
    // exists in no version.
    EXPECT_EQ(names.extraction_max_num_features,
              "SiftExtraction.max_num_features");
    EXPECT_EQ(names.matching_use_gpu, "FeatureMatching.use_gpu");
    EXPECT_EQ(names.matching_num_threads, "FeatureMatching.num_threads");
    EXPECT_EQ(names.mapper_image_list_path, "Mapper.image_list_path");
    EXPECT_EQ(names.mapper_random_seed,
              (std::vector<std::string>{"default_random_seed",
                                        "Mapper.random_seed"}));
  }
}

TEST(ShellQuote, QuotesOnlyWhatNeedsIt) {
  EXPECT_EQ(ShellQuote("--Mapper.num_threads=2"), "--Mapper.num_threads=2");
  EXPECT_EQ(ShellQuote("my images"), "'my images'");
  EXPECT_EQ(ShellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(ShellQuote(""), "''");
}

TEST_F(ColmapRunnerTest, DetectsTheVersion) {
  ColmapRunner runner = Runner();
  EXPECT_EQ(runner.Version().minor, 8);
}

TEST_F(ColmapRunnerTest, PassesArgumentsVerbatimAndLogsEverything) {
  ColmapRunner runner = Runner();
  const std::string tricky = "images; rm -rf / $(echo x) 'q'";
  const ColmapStageResult result = runner.RunStage(
      "extract", {"feature_extractor", "--image_path", tricky}, {});
  EXPECT_FALSE(result.reused);
  EXPECT_EQ(Read(dir_ / "args.txt"),
            "feature_extractor\n--image_path\n" + tricky + "\n");
  EXPECT_NE(Read(result.log_path).find("glog_to_stderr=1"), std::string::npos);
  const std::string commands = Read(dir_ / "ws" / "commands.txt");
  EXPECT_NE(commands.find("feature_extractor --image_path 'images; rm -rf"),
            std::string::npos)
      << commands;
}

// The argv names a list file whose content it does not hold: a stage whose
// list changed is run anew, also by a later program run (a run stopped
// after writing the list and before running the stage must not leave a
// marker that still matches).
TEST_F(ColmapRunnerTest, ReusesAStageOnlyWithTheSameListContent) {
  const std::string output = (dir_ / "ws" / "database.db").string();
  std::ofstream(output) << "x";
  const std::string list = (dir_ / "ws" / "image_list.txt").string();
  std::ofstream(list) << "a.png\nb.png\n";
  const std::vector<std::string> arguments = {
      "feature_extractor", "--ImageReader.image_list_path", list};
  EXPECT_FALSE(Runner().RunStage("extract", arguments, {output}).reused);
  EXPECT_TRUE(Runner().WillReuse("extract", arguments, {output}));
  std::ofstream(list) << "a.png\nc.png\n";
  EXPECT_FALSE(Runner().WillReuse("extract", arguments, {output}));
  EXPECT_FALSE(Runner().RunStage("extract", arguments, {output}).reused);
  EXPECT_TRUE(Runner().RunStage("extract", arguments, {output}).reused);
}

TEST_F(ColmapRunnerTest, ReusesFinishedStagesOnlyWithTheSameArguments) {
  // One runner per program run: reuse is across runs on one workspace.
  const std::string output = (dir_ / "ws" / "database.db").string();
  std::ofstream(output) << "x";
  EXPECT_FALSE(
      Runner()
          .RunStage("extract", {"feature_extractor", "--a", "1"}, {output})
          .reused);
  EXPECT_TRUE(Runner().WillReuse(
      "extract", {"feature_extractor", "--a", "1"}, {output}));
  EXPECT_TRUE(
      Runner()
          .RunStage("extract", {"feature_extractor", "--a", "1"}, {output})
          .reused);
  EXPECT_FALSE(
      Runner()
          .RunStage("extract", {"feature_extractor", "--a", "2"}, {output})
          .reused);
  fs::remove(output);
  EXPECT_FALSE(Runner().WillReuse(
      "extract", {"feature_extractor", "--a", "2"}, {output}));
  EXPECT_FALSE(
      Runner()
          .RunStage("extract", {"feature_extractor", "--a", "2"}, {output})
          .reused);
}

TEST_F(ColmapRunnerTest, AStageRunAnewMakesEveryLaterStageRunAnew) {
  {
    ColmapRunner first = Runner();
    first.RunStage("extract", {"feature_extractor"}, {});
    first.RunStage("match", {"spatial_matcher"}, {});
    first.RunStage("map", {"mapper"}, {});
  }
  ColmapRunner second = Runner();
  EXPECT_TRUE(second.RunStage("extract", {"feature_extractor"}, {}).reused);
  EXPECT_FALSE(
      second.RunStage("match", {"spatial_matcher", "--changed"}, {}).reused);
  // Same arguments as before, but its input (the matches) changed.
  EXPECT_FALSE(second.WillReuse("map", {"mapper"}, {}));
  EXPECT_FALSE(second.RunStage("map", {"mapper"}, {}).reused);

  ColmapRunner third = Runner();
  EXPECT_TRUE(third.WillReuse("extract", {"feature_extractor"}, {}));
  third.RunLaterStagesAnew();  // e.g. the caller rewrote the database
  EXPECT_FALSE(third.RunStage("extract", {"feature_extractor"}, {}).reused);
}

TEST_F(ColmapRunnerTest, ExplainsAnAbort) {
  WriteFake("3.8", 134);
  ColmapRunner runner = Runner();
  try {
    runner.RunStage("map", {"mapper"}, {});
    FAIL() << "no error for exit code 134";
  } catch (const ColmapError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("134"), std::string::npos) << message;
    EXPECT_NE(message.find("CHECK"), std::string::npos) << message;
    EXPECT_NE(message.find("map.log"), std::string::npos) << message;
    EXPECT_NE(message.find("Check failed: something"), std::string::npos)
        << message;
  }
  // A failed stage is not marked finished.
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "stages" / "map.done"));
}

TEST_F(ColmapRunnerTest, MissingColmapIsAClearError) {
  ColmapRunner::Options options;
  options.executable = "odomcal-no-such-colmap";
  options.workspace = (dir_ / "ws").string();
  ColmapRunner runner(options);
  try {
    runner.Version();
    FAIL() << "no error for a missing program";
  } catch (const ColmapError& error) {
    EXPECT_NE(std::string(error.what()).find("not found"), std::string::npos);
  }
}

// A fake colmap whose `mapper` runs the shell command in its last argument:
// stages that wait for each other.
std::string WriteWaitingFake(const fs::path& dir) {
  return WriteFakeColmapScript(dir,
                               "for last in \"$@\"; do :; done\n"
                               "eval \"$last\"\n");
}

// Two stages started side by side run at the same time: the first ends
// well only once the second has started (it waits up to 20 s for its
// mark). Each is marked finished only by its Finish, and its lines go to
// the listener of the Poll that read them.
TEST_F(ColmapRunnerTest, StagesStartedSideBySideRunAtTheSameTime) {
  fake_ = WriteWaitingFake(dir_);
  ColmapRunner runner = Runner();
  const std::string mark = (dir_ / "second_started").string();
  RunningStage first = runner.StartStage(
      "mapper_a",
      {"mapper",
       "i=0; while [ ! -f " + mark +
           " ]; do i=$((i+1)); [ $i -gt 200 ] && exit 3; sleep 0.1; done; "
           "echo first done"},
      {});
  RunningStage second = runner.StartStage(
      "mapper_b", {"mapper", "echo second; touch " + mark}, {});
  std::vector<std::string> lines;
  const OutputLineCallback listener = [&lines](const std::string& line) {
    lines.push_back(line);
  };
  second.WaitForEnd();
  first.WaitForEnd(listener);
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "stages" / "mapper_a.done"));
  EXPECT_NO_THROW(first.Finish());
  EXPECT_NO_THROW(second.Finish());
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "stages" / "mapper_a.done"));
  EXPECT_TRUE(fs::exists(dir_ / "ws" / "stages" / "mapper_b.done"));
  EXPECT_EQ(lines, std::vector<std::string>{"first done"});
  EXPECT_NE(Read(dir_ / "ws" / "logs" / "mapper_b.log").find("second"),
            std::string::npos);
}

// A stage dropped while COLMAP runs stops it and reaps it: no process (not
// even a zombie) is left with its pid, and the stage never wrote its mark.
TEST_F(ColmapRunnerTest, AStageDroppedWhileRunningIsStopped) {
  fake_ = WriteWaitingFake(dir_);
  ColmapRunner runner = Runner();
  const fs::path pid_file = dir_ / "pid";
  const fs::path mark = dir_ / "ran_to_the_end";
  {
    RunningStage stage = runner.StartStage(
        "mapper_a",
        // The pid is written aside and renamed: the test must not read the
        // file between its creation and the write.
        {"mapper",
         "echo $$ > " + pid_file.string() + ".tmp; mv " + pid_file.string() +
             ".tmp " + pid_file.string() +
             "; sleep 30 & child=$!; trap 'kill $child; exit 143' TERM; "
             "wait $child; touch " +
             mark.string()},
        {});
    for (int i = 0; i < 200 && !fs::exists(pid_file); ++i) {
      EXPECT_FALSE(stage.Poll());
      ::usleep(50000);
    }
  }
  std::ifstream file(pid_file);
  pid_t pid = 0;
  ASSERT_TRUE(file >> pid);
  EXPECT_EQ(::kill(pid, 0), -1);
  EXPECT_EQ(errno, ESRCH);
  EXPECT_FALSE(fs::exists(mark));
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "stages" / "mapper_a.done"));
}

// Failures of a started stage come from its Finish: a missing program, and
// an exit code, as RunStage reports them.
TEST_F(ColmapRunnerTest, AStartedStageReportsItsFailureWhenFinished) {
  WriteFake("3.8", 134);
  ColmapRunner runner = Runner();
  RunningStage failing = runner.StartStage("map", {"mapper"}, {});
  failing.WaitForEnd();
  EXPECT_THROW(failing.Finish(), ColmapError);
  EXPECT_FALSE(fs::exists(dir_ / "ws" / "stages" / "map.done"));

  ColmapRunner::Options options;
  options.executable = "odomcal-no-such-colmap";
  options.workspace = (dir_ / "ws").string();
  ColmapRunner missing(options);
  RunningStage nothing = missing.StartStage("map", {"mapper"}, {});
  EXPECT_TRUE(nothing.Poll());
  try {
    nothing.Finish();
    FAIL() << "no error for a missing program";
  } catch (const ColmapError& error) {
    EXPECT_NE(std::string(error.what()).find("not found"), std::string::npos);
  }
}

// The real program, when installed: Debian 12 ships COLMAP 3.8.
TEST(ColmapRunnerReal, DetectsInstalledColmap) {
  const fs::path workspace = fs::path(::testing::TempDir()) / "runner_real";
  fs::create_directories(workspace);
  ColmapRunner::Options options;
  options.workspace = workspace.string();
  ColmapRunner runner(options);
  try {
    const ColmapVersion& version = runner.Version();
    EXPECT_GE(version.major, 3);
  } catch (const ColmapError& error) {
    GTEST_SKIP() << error.what();
  }
  fs::remove_all(workspace);
}

}  // namespace
}  // namespace odomcal

namespace odomcal {
namespace {

// The listener gets COLMAP's lines while it runs, the last one also without
// its end of line ("Matching image [2/2]" is printed before its time).
TEST(ColmapRunnerOutput, FollowsTheLogWhileTheStageRuns) {
  const fs::path dir = fs::path(::testing::TempDir()) / "runner_output";
  fs::remove_all(dir);
  fs::create_directories(dir / "ws");
  const std::string fake =
      WriteFakeColmapScript(dir,
                            "echo 'Matching image [1/2] in 0.100s'\n"
                            "sleep 0.4\n"
                            "printf 'Matching image [2/2]'\n");
  std::vector<std::string> lines;
  ColmapRunner::Options options;
  options.executable = fake;
  options.workspace = (dir / "ws").string();
  options.on_output_line = [&lines](const std::string& line) {
    lines.push_back(line);
  };
  ColmapRunner runner(options);
  runner.RunStage("spatial_matcher", {"spatial_matcher"}, {});
  EXPECT_EQ(lines,
            (std::vector<std::string>{"Matching image [1/2] in 0.100s",
                                      "Matching image [2/2]"}));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace odomcal
