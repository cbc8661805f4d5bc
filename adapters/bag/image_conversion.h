// sensor_msgs/Image and sensor_msgs/CompressedImage -> image files.
//
// Raw images become a cv::Mat that cv::imwrite stores losslessly as PNG:
//   mono8                                   -> CV_8UC1
//   mono16 (big- or little-endian bytes)    -> CV_16UC1, host byte order
//   rgb8, bgr8, rgba8, bgra8                -> CV_8UC3, BGR (alpha dropped)
//   bayer_rggb8, bayer_bggr8, bayer_gbrg8,
//   bayer_grbg8                             -> CV_8UC3, BGR, demosaiced by
//                                              OpenCV's bilinear cvtColor
// Pixel (0, 0) is the top-left pixel, as in ROS; no resampling or cropping,
// so the camera's pixel coordinates are unchanged.
//
// Compressed images are stored with their original bytes; the file type
// comes from the data's magic bytes (JPEG FF D8 FF, PNG 89 50 4E 47), the
// message's format string is only a hint.
//
// Problems throw FormatError("<context>: <problem>"), context naming the bag
// and topic: an unsupported encoding (named), a step shorter than width times
// the bytes per pixel, a data size other than step * height, compressed data
// that is neither JPEG nor PNG.
#pragma once

#include "odomcal/adapters/bag/ros_messages.h"

#include <opencv2/core.hpp>

#include <string>

namespace odomcal::bag {

// The image as a Mat that owns its pixels (see the top of this file).
cv::Mat ImageMessageToMat(const ImageMessage& image,
                          const std::string& context);

// ".jpg" or ".png", from the magic bytes of image.data.
std::string CompressedImageExtension(const CompressedImageMessage& image,
                                     const std::string& context);

}  // namespace odomcal::bag
