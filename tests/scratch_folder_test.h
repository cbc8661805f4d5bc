// A test fixture with a fresh folder of its own: <TempDir>/<prefix><test
// name>, emptied before the test and removed after it (kept when
// ODOMCAL_KEEP_TEST_FILES is set, to look at what a failing test wrote).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <utility>

namespace odomcal {

class ScratchFolderTest : public ::testing::Test {
 protected:
  explicit ScratchFolderTest(std::string prefix) : prefix_(std::move(prefix)) {}

  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ =
        std::filesystem::path(::testing::TempDir()) / (prefix_ + info->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (std::getenv("ODOMCAL_KEEP_TEST_FILES") == nullptr) {
      std::filesystem::remove_all(dir_);
    }
  }

  // `name` inside the folder.
  std::string Path(const std::string& name) const {
    return (dir_ / name).string();
  }

  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace odomcal
