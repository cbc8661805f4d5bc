// Every command line odomcal builds, checked by tests/fake_colmap/
// fake_colmap.py emulating each COLMAP release from 3.8 to 4.1.1 (and
// GLOMAP): the fake accepts exactly the option names that release
// registers, as read from COLMAP's sources at its tag, and here runs
// `true` instead of COLMAP, so only the names are tested.
#include "odomcal/plugin/colmap/colmap_runner.h"
#include "odomcal/plugin/colmap/reconstruction_pipeline.h"
#include "odomcal/plugin/colmap/reconstruction_stages.h"

#include <sys/wait.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kReleases = {
    "3.8", "3.9.1", "3.10", "3.11.1", "3.12.6", "3.13.0", "4.0.4", "4.1.1"};

std::string FakeCommand(const std::string& emulate) {
  return std::string("/usr/bin/python3 ") + ODOMCAL_FAKE_COLMAP +
         " --emulate " + emulate + " --real true";
}

// The exit code of the fake emulating `emulate` on `arguments`.
int RunFake(const std::string& emulate,
            const std::vector<std::string>& arguments) {
  std::string command = FakeCommand(emulate);
  for (const std::string& argument : arguments) {
    command += " " + ShellQuote(argument);
  }
  command += " 2>/dev/null";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The release's banner, as the fake prints it for `help`, parsed.
ColmapVersion VersionOf(const std::string& emulate) {
  FILE* pipe = ::popen((FakeCommand(emulate) + " help").c_str(), "r");
  std::string first_line;
  if (pipe != nullptr) {
    char buffer[256];
    bool first = true;
    while (std::fgets(buffer, sizeof(buffer), pipe) != nullptr) {
      if (first) first_line = buffer;
      first = false;
    }
    ::pclose(pipe);
  }
  while (!first_line.empty() && first_line.back() == '\n')
    first_line.pop_back();
  return ParseColmapVersion(first_line);
}

ReconstructionOptions OptionsWith(const std::string& matcher) {
  ReconstructionOptions run;
  run.image_path = "images";
  run.workspace_path = "ws";
  run.camera_params = "260,260,160,120";
  run.matcher = matcher;
  return run;
}

TEST(ColmapCommandLines, EveryReleaseAcceptsTheNamesOdomcalPasses) {
  for (const std::string& release : kReleases) {
    SCOPED_TRACE(release);
    const ColmapVersion version = VersionOf(release);
    ASSERT_EQ(version.ToString().substr(0, 3), release.substr(0, 3));
    reconstruction::MatchingRound round;
    round.database = "ws/database.db";
    EXPECT_EQ(RunFake(release,
                      reconstruction::FeatureExtractorArguments(
                          OptionsWith("odometry"), version, round.database)),
              0);
    for (const std::string matcher : {"odometry", "spatial", "sequential"}) {
      SCOPED_TRACE(matcher);
      EXPECT_EQ(RunFake(release,
                        reconstruction::MatcherArguments(
                            matcher, round, OptionsWith(matcher), version)),
                0);
    }
    EXPECT_EQ(RunFake(release,
                      reconstruction::MapperArguments(OptionsWith("odometry"),
                                                      version,
                                                      round.database,
                                                      "ws/out",
                                                      "ws/list.txt",
                                                      3,
                                                      2)),
              0);
    const reconstruction::MapperCommand global =
        reconstruction::GlobalMapperCommand(OptionsWith("odometry"),
                                            version,
                                            round.database,
                                            fs::temp_directory_path(),
                                            "ws/list.txt",
                                            3,
                                            2);
    const bool glomap = global.program == ColmapProgram::kGlomap;
    EXPECT_EQ(glomap, !version.AtLeast(4, 0));
    EXPECT_EQ(RunFake(glomap ? "glomap" : release, global.arguments), 0);
  }
}

// The control: a name from another release is refused, so the test above
// can fail.
TEST(ColmapCommandLines, TheFakeRefusesAnotherReleasesNames) {
  reconstruction::MatchingRound round;
  round.database = "ws/database.db";
  const std::vector<std::string> old_mapper =
      reconstruction::MapperArguments(OptionsWith("odometry"),
                                      VersionOf("3.8"),
                                      round.database,
                                      "out",
                                      "list",
                                      3,
                                      2);
  EXPECT_EQ(RunFake("4.1.1", old_mapper), 1);
  const std::vector<std::string> new_extractor =
      reconstruction::FeatureExtractorArguments(
          OptionsWith("odometry"), VersionOf("4.1.1"), round.database);
  EXPECT_EQ(RunFake("3.12.6", new_extractor), 1);
  std::vector<std::string> spatial = reconstruction::MatcherArguments(
      "spatial", round, OptionsWith("spatial"), VersionOf("3.8"));
  EXPECT_EQ(RunFake("3.10", spatial), 1);  // SpatialMatching.is_gps
  EXPECT_EQ(RunFake("3.13.0", {"global_mapper", "--database_path", "x"}), 1);
}

}  // namespace
}  // namespace odomcal
