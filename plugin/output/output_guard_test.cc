#include "odomcal/plugin/output/output_guard.h"

#include "odomcal/plugin/output/output_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

class OutputGuard : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_guard_") + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "data");
    std::ofstream(dir_ / "data" / "odometry.csv") << "t,x,y,yaw\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  // The message CheckOutputsApartFromInputs throws, or "" when it accepts.
  static std::string Refusal(const GuardedPaths& paths) {
    try {
      CheckOutputsApartFromInputs(paths);
    } catch (const OutputError& error) {
      return error.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(OutputGuard, AcceptsSeparateFilesAndFolders) {
  GuardedPaths paths;
  paths.inputs = {{Path("data/odometry.csv"), "--odometry"},
                  {Path("data"), "--image_path"},
                  {"", "--image_timestamps"}};
  paths.output_files = {{Path("result.json"), "--output"}};
  paths.output_folders = {{Path("out"), "--output_path"}};
  EXPECT_EQ(Refusal(paths), "");
}

TEST_F(OutputGuard, RefusesAnOutputThatIsAnInput) {
  GuardedPaths paths;
  paths.inputs = {{Path("data/odometry.csv"), "--odometry"}};
  paths.output_files = {{Path("data/../data/odometry.csv"), "--output"}};
  EXPECT_EQ(Refusal(paths),
            Path("data/../data/odometry.csv") + " (--output) is the input " +
                Path("data/odometry.csv") +
                " (--odometry); odomcal never writes over an input");
}

TEST_F(OutputGuard, RefusesSymbolicAndHardLinksOfAnInput) {
  fs::create_symlink(dir_ / "data" / "odometry.csv", dir_ / "symbolic.csv");
  fs::create_hard_link(dir_ / "data" / "odometry.csv", dir_ / "hard.csv");
  fs::create_directory_symlink(dir_ / "data", dir_ / "data_link");
  GuardedPaths paths;
  paths.inputs = {{Path("data/odometry.csv"), "--odometry"}};
  for (const char* alias : {"symbolic.csv", "data_link/odometry.csv"}) {
    paths.output_files = {{Path(alias), "--output"}};
    EXPECT_EQ(Refusal(paths),
              Path(alias) +
                  " (--output) resolves through a symbolic link to the input " +
                  Path("data/odometry.csv") +
                  " (--odometry); odomcal never writes over an input");
  }
  paths.output_files = {{Path("hard.csv"), "--output"}};
  EXPECT_EQ(Refusal(paths),
            Path("hard.csv") + " (--output) is a hard link to the input " +
                Path("data/odometry.csv") +
                " (--odometry); odomcal never writes over an input");
}

TEST_F(OutputGuard, RefusesAnOutputInsideAnInputFolder) {
  GuardedPaths paths;
  paths.inputs = {{Path("data/"), "--model_path"}};
  paths.output_folders = {{Path("data/out"), "--output_path"}};
  EXPECT_EQ(Refusal(paths),
            Path("data/out") + " (--output_path) is inside the input folder " +
                Path("data/") +
                " (--model_path); odomcal never writes into an input");
  // A sibling whose name starts like the input's is not inside it.
  paths.output_folders = {{Path("data_out"), "--output_path"}};
  EXPECT_EQ(Refusal(paths), "");
}

TEST_F(OutputGuard, RefusesAnOutputFolderHoldingAnInput) {
  GuardedPaths paths;
  paths.inputs = {{Path("data/odometry.csv"), "--odometry"}};
  paths.output_folders = {{dir_.string(), "--workspace_path"}};
  EXPECT_EQ(Refusal(paths),
            dir_.string() + " (--workspace_path) holds the input " +
                Path("data/odometry.csv") +
                " (--odometry); odomcal never writes into a folder that "
                "holds an input");
  // A file output cannot hold anything.
  paths.output_folders.clear();
  paths.output_files = {{Path("data"), "--output"}};
  paths.inputs = {{Path("data/odometry.csv"), "--odometry"}};
  EXPECT_EQ(Refusal(paths), "");
}

TEST_F(OutputGuard, RefusesTwoOutputsInOneFile) {
  GuardedPaths paths;
  paths.output_files = {{Path("r.yaml"), "--output"},
                        {Path("r.yaml"), "the YAML beside --output"}};
  EXPECT_EQ(Refusal(paths),
            Path("r.yaml") + " (the YAML beside --output) is the output " +
                Path("r.yaml") +
                " (--output); two outputs cannot share a file");
}

}  // namespace
}  // namespace odomcal
