#include "odomcal/adapters/bag/image_conversion.h"

#include "odomcal/adapters/test_support.h"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

ImageMessage MakeImage(const std::string& encoding,
                       uint32_t width,
                       uint32_t height,
                       uint32_t step) {
  ImageMessage image;
  image.encoding = encoding;
  image.width = width;
  image.height = height;
  image.step = step;
  image.data.assign(static_cast<size_t>(step) * height, 0);
  return image;
}

// Mosaics a uniform colour by hand: `pattern` names the colour of the
// top-left 2x2 block row by row, as ROS's encoding names do ("rggb").
ImageMessage Mosaic(const std::string& pattern,
                    uint8_t r,
                    uint8_t g,
                    uint8_t b) {
  ImageMessage image = MakeImage("bayer_" + pattern + "8", 8, 6, 8);
  for (uint32_t row = 0; row < image.height; ++row) {
    for (uint32_t col = 0; col < image.width; ++col) {
      const char channel = pattern[(row % 2) * 2 + col % 2];
      image.data[row * image.step + col] =
          channel == 'r' ? r : (channel == 'g' ? g : b);
    }
  }
  return image;
}

TEST(ImageConversionTest, BayerPatternsKeepTheColours) {
  for (const char* pattern : {"rggb", "bggr", "gbrg", "grbg"}) {
    // Red, then a colour with three distinct channels.
    for (const cv::Vec3b& rgb :
         {cv::Vec3b(220, 0, 0), cv::Vec3b(200, 90, 30)}) {
      const cv::Mat bgr =
          ImageMessageToMat(Mosaic(pattern, rgb[0], rgb[1], rgb[2]), "t");
      ASSERT_EQ(bgr.type(), CV_8UC3);
      ASSERT_EQ(bgr.rows, 6);
      ASSERT_EQ(bgr.cols, 8);
      // Interior pixels, away from the border's extrapolation.
      for (int row = 2; row < 4; ++row) {
        for (int col = 2; col < 6; ++col) {
          const cv::Vec3b pixel = bgr.at<cv::Vec3b>(row, col);
          EXPECT_EQ(pixel[2], rgb[0])
              << pattern << " red at " << row << "," << col;
          EXPECT_EQ(pixel[1], rgb[1]) << pattern << " green";
          EXPECT_EQ(pixel[0], rgb[2]) << pattern << " blue";
        }
      }
    }
  }
}

TEST(ImageConversionTest, Mono8DropsRowPadding) {
  ImageMessage image = MakeImage("mono8", 3, 2, 5);
  const std::vector<uint8_t> data = {1, 2, 3, 99, 99, 4, 5, 6, 99, 99};
  image.data = data;
  const cv::Mat mat = ImageMessageToMat(image, "t");
  ASSERT_EQ(mat.type(), CV_8UC1);
  EXPECT_EQ(mat.at<uint8_t>(0, 2), 3);
  EXPECT_EQ(mat.at<uint8_t>(1, 0), 4);
  EXPECT_EQ(mat.at<uint8_t>(1, 2), 6);
}

TEST(ImageConversionTest, Mono16HonoursByteOrderAndStays16Bit) {
  ImageMessage image = MakeImage("mono16", 2, 1, 4);
  image.data = {0x01, 0x02, 0xA0, 0x0B};
  image.is_bigendian = true;
  cv::Mat mat = ImageMessageToMat(image, "t");
  ASSERT_EQ(mat.type(), CV_16UC1);
  EXPECT_EQ(mat.at<uint16_t>(0, 0), 0x0102);
  EXPECT_EQ(mat.at<uint16_t>(0, 1), 0xA00B);
  image.is_bigendian = false;
  mat = ImageMessageToMat(image, "t");
  EXPECT_EQ(mat.at<uint16_t>(0, 0), 0x0201);
  EXPECT_EQ(mat.at<uint16_t>(0, 1), 0x0BA0);

  // The PNG keeps all 16 bits.
  const std::string path =
      (std::filesystem::path(::testing::TempDir()) / "mono16_test.png")
          .string();
  ASSERT_TRUE(cv::imwrite(path, mat));
  const cv::Mat read = cv::imread(path, cv::IMREAD_UNCHANGED);
  std::filesystem::remove(path);
  ASSERT_EQ(read.type(), CV_16UC1);
  EXPECT_EQ(read.at<uint16_t>(0, 1), 0x0BA0);
}

TEST(ImageConversionTest, ColourEncodingsBecomeBgr) {
  struct Case {
    const char* encoding;
    std::vector<uint8_t> pixel;  // the bytes of one pixel
  };
  // Every case is the colour r = 10, g = 20, b = 30.
  const Case cases[] = {{"rgb8", {10, 20, 30}},
                        {"bgr8", {30, 20, 10}},
                        {"rgba8", {10, 20, 30, 255}},
                        {"bgra8", {30, 20, 10, 128}}};
  for (const Case& c : cases) {
    const uint32_t bytes = static_cast<uint32_t>(c.pixel.size());
    ImageMessage image = MakeImage(c.encoding, 2, 2, 2 * bytes + 3);
    for (uint32_t row = 0; row < 2; ++row) {
      for (uint32_t col = 0; col < 2; ++col) {
        std::copy(c.pixel.begin(),
                  c.pixel.end(),
                  image.data.begin() + row * image.step + col * bytes);
      }
    }
    const cv::Mat mat = ImageMessageToMat(image, "t");
    ASSERT_EQ(mat.type(), CV_8UC3) << c.encoding;
    EXPECT_EQ(mat.at<cv::Vec3b>(1, 1), cv::Vec3b(30, 20, 10)) << c.encoding;
  }
}

TEST(ImageConversionTest, RefusesBadLayoutsAndEncodings) {
  ImageMessage image = MakeImage("rgb8", 4, 2, 11);
  std::string error =
      FormatErrorOf([&] { ImageMessageToMat(image, "b.bag: /cam"); });
  EXPECT_TRUE(Contains(error, "b.bag: /cam: step 11")) << error;

  image = MakeImage("mono8", 4, 2, 4);
  image.data.pop_back();
  error = FormatErrorOf([&] { ImageMessageToMat(image, "b.bag: /cam"); });
  EXPECT_TRUE(Contains(error, "7 bytes")) << error;

  image = MakeImage("yuv422", 4, 2, 8);
  error = FormatErrorOf([&] { ImageMessageToMat(image, "b.bag: /cam"); });
  EXPECT_TRUE(Contains(error, "'yuv422'")) << error;
}

TEST(ImageConversionTest, CompressedTypeComesFromTheBytes) {
  const cv::Mat pixels(4, 4, CV_8UC3, cv::Scalar(1, 2, 3));
  CompressedImageMessage image;
  image.format = "png";  // a wrong hint
  ASSERT_TRUE(cv::imencode(".jpg", pixels, image.data));
  EXPECT_EQ(CompressedImageExtension(image, "t"), ".jpg");
  image.format = "jpeg";
  ASSERT_TRUE(cv::imencode(".png", pixels, image.data));
  EXPECT_EQ(CompressedImageExtension(image, "t"), ".png");

  image.data = {'B', 'M', 0, 0, 0};
  const std::string error =
      FormatErrorOf([&] { CompressedImageExtension(image, "b.bag: /cam"); });
  EXPECT_TRUE(Contains(error, "b.bag: /cam: compressed image")) << error;
  EXPECT_TRUE(Contains(error, "42 4D 00 00")) << error;
}

}  // namespace
}  // namespace odomcal::bag
