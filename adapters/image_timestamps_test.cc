#include "odomcal/adapters/image_timestamps.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace odomcal {
namespace {

std::string WriteTextFile(const std::string& name, const std::string& text) {
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / ("odomcal_stamps_" + name))
          .string();
  std::ofstream stream(path, std::ios::binary | std::ios::trunc);
  stream << text;
  EXPECT_TRUE(stream.good()) << path;
  return path;
}

TEST(ReadImageTimestampsCsv, HeaderSubFoldersAndExactSeconds) {
  const std::string path =
      WriteTextFile("header.csv",
                    "image_name,timestamp\n"
                    "# comment\n"
                    "cam0/000001.png, 1403636579.763555584\n"
                    "\n"
                    "cam1/000001.png,1403636579.5\r\n"
                    "000001.png,-0.25\n");
  const std::map<std::string, int64_t> stamps =
      ReadImageTimestampsCsv(path, TimeUnit::kSeconds);
  ASSERT_EQ(stamps.size(), 3u);
  EXPECT_EQ(stamps.at("cam0/000001.png"), 1403636579763555584);
  EXPECT_EQ(stamps.at("cam1/000001.png"), 1403636579500000000);
  EXPECT_EQ(stamps.at("000001.png"), -250000000);
}

TEST(ReadImageTimestampsCsv, NoHeaderAndOtherUnits) {
  const std::string path =
      WriteTextFile("no_header.csv", "a.png,1500\nb.png,2500.5\n");
  const std::map<std::string, int64_t> ms =
      ReadImageTimestampsCsv(path, TimeUnit::kMilliseconds);
  EXPECT_EQ(ms.at("a.png"), 1500000000);
  EXPECT_EQ(ms.at("b.png"), 2500500000);
  const std::map<std::string, int64_t> ns = ReadImageTimestampsCsv(
      WriteTextFile("ns.csv", "a.png,1500\n"), TimeUnit::kNanoseconds);
  EXPECT_EQ(ns.at("a.png"), 1500);
}

void ExpectCsvError(const std::string& name,
                    const std::string& text,
                    const std::string& where,
                    const std::string& part) {
  SCOPED_TRACE(name);
  const std::string path = WriteTextFile(name, text);
  const std::string error =
      FormatErrorOf([&] { ReadImageTimestampsCsv(path, TimeUnit::kSeconds); });
  EXPECT_TRUE(Contains(error, path + where)) << error;
  EXPECT_TRUE(Contains(error, part)) << error;
}

TEST(ReadImageTimestampsCsv, Errors) {
  ExpectCsvError("dup.csv",
                 "name,t\na.png,1\nb.png,2\na.png,3\n",
                 ":4: ",
                 "image 'a.png' is listed twice (first on line 2)");
  ExpectCsvError("nan.csv", "a.png,nan\n", ":1: ", "timestamp of 'a.png'");
  ExpectCsvError(
      "minus_inf.csv", "a.png,-INF\n", ":1: ", "timestamp of 'a.png'");
  ExpectCsvError(
      "inf.csv", "a.png,1\nb.png,inf\n", ":2: ", "timestamp of 'b.png'");
  ExpectCsvError("exp.csv", "a.png,1e9\n", ":1: ", "exponents");
  ExpectCsvError(
      "fields.csv", "a.png,1,2\n", ":1: ", "expected 2 comma-separated fields");
  ExpectCsvError("one_field.csv", "a.png 1\n", ":1: ", "got 1");
  ExpectCsvError("empty_name.csv", ",1\n", ":1: ", "empty image name");
  ExpectCsvError(
      "ns_as_s.csv", "a.png,1403636579763555584\n", ":1: ", "time unit");
  ExpectCsvError("empty.csv", "# nothing\n", ": ", "no image timestamps");
  ExpectCsvError(
      "header_only.csv", "image_name,timestamp\n", ": ", "no image timestamps");
  EXPECT_THROW(ReadImageTimestampsCsv(WriteTextFile("x", "") + ".missing",
                                      TimeUnit::kSeconds),
               FormatError);
}

TEST(TimestampFromImageName, IntegerStemsAreNanoseconds) {
  std::string error;
  EXPECT_EQ(
      TimestampFromImageName("1403636579763555584.png", std::nullopt, &error),
      1403636579763555584);
  EXPECT_EQ(TimestampFromImageName(
                "cam0/1403636579763555584.png", std::nullopt, &error),
            1403636579763555584);
  EXPECT_EQ(TimestampFromImageName("a.b/c/000123.jpeg", std::nullopt, &error),
            123);
  EXPECT_EQ(TimestampFromImageName("1403636579763555584", std::nullopt, &error),
            1403636579763555584);
}

TEST(TimestampFromImageName, DecimalStemsAreSeconds) {
  std::string error;
  EXPECT_EQ(
      TimestampFromImageName("1403636579.763555.png", std::nullopt, &error),
      1403636579763555000);
  EXPECT_EQ(TimestampFromImageName(
                "left/1403636579.763555584.jpg", std::nullopt, &error),
            1403636579763555584);
  // Without an extension the digits after the point are the fraction.
  EXPECT_EQ(TimestampFromImageName("12.5", std::nullopt, &error), 12500000000);
}

TEST(TimestampFromImageName, UnitOverrideAppliesToBothForms) {
  std::string error;
  EXPECT_EQ(TimestampFromImageName("1500.png", TimeUnit::kMilliseconds, &error),
            1500000000);
  EXPECT_EQ(
      TimestampFromImageName("cam/1500.5.png", TimeUnit::kMicroseconds, &error),
      1500500);
  EXPECT_EQ(
      TimestampFromImageName("1403636579.png", TimeUnit::kSeconds, &error),
      1403636579000000000);
}

TEST(TimestampFromImageName, NonNumericNamesSayWhy) {
  for (const char* name : {"frame_000123.png",
                           "cam0/a1.png",
                           ".png",
                           "1.2.3",
                           "-5.png",
                           "1e9.png",
                           "cam0/",
                           "1 2.png"}) {
    SCOPED_TRACE(name);
    std::string error;
    EXPECT_FALSE(
        TimestampFromImageName(name, std::nullopt, &error).has_value());
    EXPECT_TRUE(Contains(error, std::string("image name '") + name + "'"))
        << error;
  }
  std::string error;
  EXPECT_FALSE(TimestampFromImageName(
                   "1403636579763555584.png", TimeUnit::kSeconds, &error)
                   .has_value());
  EXPECT_TRUE(Contains(error, "time unit")) << error;
  EXPECT_FALSE(TimestampFromImageName("x.png", std::nullopt, nullptr));
}

TEST(ImageTimestamps, LookupFromCsvUsesFullRelativeNames) {
  const std::string path =
      WriteTextFile("lookup.csv", "cam0/000001.png,1.5\ncam1/000001.png,2\n");
  const ImageTimestamps stamps =
      ImageTimestamps::FromCsv(path, TimeUnit::kSeconds);
  std::string why;
  EXPECT_EQ(stamps.Lookup("cam0/000001.png", &why), 1500000000);
  EXPECT_EQ(stamps.Lookup("cam1/000001.png", &why), 2000000000);
  EXPECT_FALSE(stamps.Lookup("000001.png", &why).has_value());
  EXPECT_EQ(why, "'000001.png' is not listed in " + path);
  EXPECT_EQ(stamps.source(), path);
}

TEST(ImageTimestamps, LookupFromFileNames) {
  const ImageTimestamps stamps = ImageTimestamps::FromFileNames(std::nullopt);
  std::string why;
  EXPECT_EQ(stamps.Lookup("cam0/1403636579763555584.png", &why),
            1403636579763555584);
  EXPECT_FALSE(stamps.Lookup("cam0/frame.png", &why).has_value());
  EXPECT_TRUE(Contains(why, "not a time")) << why;
  EXPECT_EQ(stamps.source(), "image file names");
  const ImageTimestamps in_us =
      ImageTimestamps::FromFileNames(TimeUnit::kMicroseconds);
  EXPECT_EQ(in_us.Lookup("7.png", &why), 7000);
}

TEST(ReadImageTimestampsCsv, QuotedNamesAndByteOrderMark) {
  const std::string path =
      WriteTextFile("quoted.csv",
                    "\xEF\xBB\xBF\"image_name\",\"timestamp\"\n"
                    "\"000001.png\",1403636579.5\n"
                    "\"cam0/000002.png\" , \"1403636579.75\"\n");
  const std::map<std::string, int64_t> stamps =
      ReadImageTimestampsCsv(path, TimeUnit::kSeconds);
  ASSERT_EQ(stamps.size(), 2u);
  EXPECT_EQ(stamps.at("000001.png"), 1403636579500000000);
  EXPECT_EQ(stamps.at("cam0/000002.png"), 1403636579750000000);
  // Without a header, a BOM does not hide the first image.
  const std::string bare = WriteTextFile("bom.csv",
                                         "\xEF\xBB\xBF"
                                         "000001.png,1.5\n");
  EXPECT_EQ(ReadImageTimestampsCsv(bare, TimeUnit::kSeconds).at("000001.png"),
            1500000000);
}

TEST(ImageTimestamps, SayHowTheTimesWereRead) {
  EXPECT_EQ(ImageTimestamps::FromFileNames(TimeUnit::kMilliseconds).how_read(),
            "read from the image names as ms");
  EXPECT_EQ(
      ImageTimestamps::FromFileNames(std::nullopt).how_read(),
      "read from the image names as ns (s for names with a decimal point)");
  const std::string path = WriteTextFile("how.csv", "a.png,1\n");
  EXPECT_EQ(ImageTimestamps::FromCsv(path, TimeUnit::kMicroseconds).how_read(),
            "read from " + path + " in us");
}

}  // namespace
}  // namespace odomcal
