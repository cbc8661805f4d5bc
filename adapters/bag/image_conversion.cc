#include "odomcal/adapters/bag/image_conversion.h"

#include "odomcal/adapters/format_error.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <string>
#include <vector>

namespace odomcal::bag {
namespace {

struct RawEncoding {
  const char* name;
  int bytes_per_pixel;
  int mat_type;  // of the message's pixels
  int cvt_code;  // to BGR, or -1 when the pixels are stored as they are
};

// OpenCV names a Bayer pattern by the 2x2 block starting at the second row
// and second column, ROS by the block at the top-left: ROS's RGGB is
// OpenCV's BG, and so on (checked in image_conversion_test.cc).
constexpr RawEncoding kRawEncodings[] = {
    {"mono8", 1, CV_8UC1, -1},
    {"mono16", 2, CV_16UC1, -1},
    {"rgb8", 3, CV_8UC3, cv::COLOR_RGB2BGR},
    {"bgr8", 3, CV_8UC3, -1},
    {"rgba8", 4, CV_8UC4, cv::COLOR_RGBA2BGR},
    {"bgra8", 4, CV_8UC4, cv::COLOR_BGRA2BGR},
    {"bayer_rggb8", 1, CV_8UC1, cv::COLOR_BayerBG2BGR},
    {"bayer_bggr8", 1, CV_8UC1, cv::COLOR_BayerRG2BGR},
    {"bayer_gbrg8", 1, CV_8UC1, cv::COLOR_BayerGR2BGR},
    {"bayer_grbg8", 1, CV_8UC1, cv::COLOR_BayerGB2BGR},
};

const RawEncoding* FindRawEncoding(const std::string& name) {
  for (const RawEncoding& encoding : kRawEncodings) {
    if (name == encoding.name) return &encoding;
  }
  return nullptr;
}

std::string SupportedEncodings() {
  std::string names;
  for (const RawEncoding& encoding : kRawEncodings) {
    if (!names.empty()) names += ", ";
    names += encoding.name;
  }
  return names;
}

bool StartsWith(const std::vector<uint8_t>& data,
                std::initializer_list<uint8_t> magic) {
  if (data.size() < magic.size()) return false;
  return std::equal(magic.begin(), magic.end(), data.begin());
}

}  // namespace

cv::Mat ImageMessageToMat(const ImageMessage& image,
                          const std::string& context) {
  const RawEncoding* encoding = FindRawEncoding(image.encoding);
  if (encoding == nullptr) {
    throw FormatError(context + ": image encoding '" + image.encoding +
                      "' is not supported (supported: " + SupportedEncodings() +
                      ")");
  }
  // OpenCV's sizes are int; no camera comes near this bound.
  constexpr uint32_t kMaxSide = 1u << 20;
  if (image.width == 0 || image.height == 0 || image.width > kMaxSide ||
      image.height > kMaxSide) {
    throw FormatError(context + ": the image is " +
                      std::to_string(image.width) + " x " +
                      std::to_string(image.height) + " pixels");
  }
  const uint64_t row_bytes =
      static_cast<uint64_t>(image.width) * encoding->bytes_per_pixel;
  if (image.step < row_bytes) {
    throw FormatError(context + ": step " + std::to_string(image.step) +
                      " is shorter than a row of " +
                      std::to_string(image.width) + " " + encoding->name +
                      " pixels (" + std::to_string(row_bytes) + " bytes)");
  }
  const uint64_t expected = static_cast<uint64_t>(image.step) * image.height;
  if (image.data.size() != expected) {
    throw FormatError(
        context + ": data holds " + std::to_string(image.data.size()) +
        " bytes, but step * height = " + std::to_string(image.step) + " * " +
        std::to_string(image.height) + " = " + std::to_string(expected));
  }
  // A view of the message's bytes; every branch below copies out of it.
  const cv::Mat view(static_cast<int>(image.height),
                     static_cast<int>(image.width),
                     encoding->mat_type,
                     const_cast<uint8_t*>(image.data.data()),
                     image.step);
  cv::Mat result;
  if (encoding->cvt_code >= 0) {
    try {
      cv::cvtColor(view, result, encoding->cvt_code);
    } catch (const cv::Exception& error) {
      throw FormatError(context + ": cannot convert the " + encoding->name +
                        " image (" + std::to_string(image.width) + " x " +
                        std::to_string(image.height) + "): " + error.err);
    }
  } else {
    result = view.clone();
  }
  if (encoding->mat_type == CV_16UC1) {
    const uint16_t probe = 1;
    uint8_t first_byte = 0;
    std::memcpy(&first_byte, &probe, 1);
    const bool host_big_endian = first_byte == 0;
    if (image.is_bigendian != host_big_endian) {
      for (int row = 0; row < result.rows; ++row) {
        auto* pixels = result.ptr<uint16_t>(row);
        for (int col = 0; col < result.cols; ++col) {
          pixels[col] =
              static_cast<uint16_t>((pixels[col] >> 8) | (pixels[col] << 8));
        }
      }
    }
  }
  return result;
}

std::string CompressedImageExtension(const CompressedImageMessage& image,
                                     const std::string& context) {
  if (StartsWith(image.data, {0xFF, 0xD8, 0xFF})) return ".jpg";
  if (StartsWith(image.data, {0x89, 0x50, 0x4E, 0x47})) return ".png";
  std::string first;
  for (size_t i = 0; i < image.data.size() && i < 4; ++i) {
    char hex[4];
    std::snprintf(hex, sizeof(hex), "%s%02X", i == 0 ? "" : " ", image.data[i]);
    first += hex;
  }
  throw FormatError(context + ": compressed image (format '" + image.format +
                    "', " + std::to_string(image.data.size()) +
                    " bytes, starting " + (first.empty() ? "<empty>" : first) +
                    ") is neither JPEG (FF D8 FF) nor PNG (89 50 4E 47)");
}

}  // namespace odomcal::bag
