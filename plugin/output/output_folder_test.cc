#include "odomcal/plugin/output/output_folder.h"

#include "odomcal/plugin/output/output_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

class OutputFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::path(::testing::TempDir()) /
           (std::string("odomcal_folder_") + info->name());
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  template <typename Action>
  static std::string Refusal(Action action) {
    try {
      action();
    } catch (const OutputError& error) {
      return error.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(OutputFolder, ClaimsCreateTheFolderAndRecordTheEntries) {
  ClaimOutputFolder(dir_.string(),
                    {"a.json", "models"},
                    ExistingOutputs::kRefuseNonEmptyFolder);
  EXPECT_TRUE(fs::is_directory(dir_));
  // Only the record: still empty for the next command.
  EXPECT_EQ(Refusal([&] {
              ClaimOutputFolder(dir_.string(),
                                {"a.json"},
                                ExistingOutputs::kRefuseNonEmptyFolder);
            }),
            "");
  fs::create_directories(dir_ / "models" / "0");
  std::ofstream(dir_ / "a.json") << "{}";
  ClaimOutputFolder(
      dir_.string(), {"a.json", "b.svg"}, ExistingOutputs::kReplaceOwn);
  RemoveOwnedOutput(dir_.string(), "models/0");
  RemoveOwnedOutput(dir_.string(), "a.json");
  RemoveOwnedOutput(dir_.string(), "missing/entry");
  EXPECT_FALSE(fs::exists(dir_ / "models" / "0"));
  EXPECT_FALSE(fs::exists(dir_ / "a.json"));
}

TEST_F(OutputFolder, NeverReplacesOrRemovesAForeignEntry) {
  fs::create_directories(dir_ / "sparse_metric" / "0");
  std::ofstream(dir_ / "project.ini") << "user's";
  const std::string refusal =
      Path("sparse_metric") + ": was not written by odomcal (not listed in " +
      Path(".odomcal_outputs") +
      "); --overwrite replaces only odomcal's own files";
  EXPECT_EQ(Refusal([&] {
              ClaimOutputFolder(dir_.string(),
                                {"calibration.json", "sparse_metric"},
                                ExistingOutputs::kReplaceOwn);
            }),
            refusal);
  EXPECT_FALSE(fs::exists(dir_ / ".odomcal_outputs"));  // nothing claimed
  EXPECT_EQ(
      Refusal([&] { RemoveOwnedOutput(dir_.string(), "sparse_metric/0"); }),
      refusal);
  EXPECT_TRUE(fs::exists(dir_ / "sparse_metric" / "0"));
  // A folder with odomcal's and the user's files: only odomcal's are claimed.
  ClaimOutputFolder(
      dir_.string(), {"calibration.json"}, ExistingOutputs::kReplaceOwn);
  EXPECT_EQ(Refusal([&] { RemoveOwnedOutput(dir_.string(), "project.ini"); }),
            Path("project.ini") +
                ": was not written by odomcal (not listed in " +
                Path(".odomcal_outputs") +
                "); --overwrite replaces only odomcal's own files");
  EXPECT_TRUE(fs::exists(dir_ / "project.ini"));
}

TEST_F(OutputFolder, WithoutOverwriteRefusesWhatExists) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "keep.txt") << "user's";
  EXPECT_EQ(
      Refusal([&] {
        ClaimOutputFolder(
            dir_.string(), {"a.csv"}, ExistingOutputs::kRefuseNonEmptyFolder);
      }),
      dir_.string() +
          ": is not empty (pass --overwrite to replace odomcal's files in it)");
  // Per entry: another file in the folder is fine, the entry itself is not.
  ClaimOutputFolder(
      dir_.string(), {"a.csv"}, ExistingOutputs::kRefuseExistingEntry);
  std::ofstream(dir_ / "a.csv") << "1";
  EXPECT_EQ(Refusal([&] {
              ClaimOutputFolder(dir_.string(),
                                {"a.csv"},
                                ExistingOutputs::kRefuseExistingEntry);
            }),
            Path("a.csv") + ": exists (pass --overwrite to replace it)");
  std::ofstream(dir_ / "not_a_folder") << "";
  EXPECT_EQ(Refusal([&] {
              ClaimOutputFolder(
                  Path("not_a_folder"), {}, ExistingOutputs::kReplaceOwn);
            }),
            Path("not_a_folder") + ": exists and is not a folder");
}

TEST(IsOdomcalResultFile, RecognisesOnlyOdomcalsJsonAndYaml) {
  const fs::path dir = fs::path(::testing::TempDir()) / "odomcal_result_file";
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    return (dir / name).string();
  };
  EXPECT_TRUE(IsOdomcalResultFile(
      write("a.json", "{\"schema\": \"odomcal.calibration\"}")));
  EXPECT_TRUE(IsOdomcalResultFile(write(
      "a.yaml",
      "%YAML:1.0\n---\nstatus: success\nmessage: \"\"\nunobservable:\n   - "
      "translation_z\n")));
  EXPECT_FALSE(IsOdomcalResultFile(write("b.json", "{\"schema\": \"other\"}")));
  EXPECT_FALSE(IsOdomcalResultFile(
      write("odometry.csv", "timestamp,x,y,yaw\n0,0,0,0\n")));
  EXPECT_FALSE(
      IsOdomcalResultFile(write("b.yaml", "%YAML:1.0\n---\nstatus: mine\n")));
  EXPECT_FALSE(IsOdomcalResultFile((dir / "missing.json").string()));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace odomcal
