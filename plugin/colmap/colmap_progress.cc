#include "odomcal/plugin/colmap/colmap_progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <regex>

namespace odomcal {
namespace {

std::string Duration(double seconds) {
  char text[32];
  if (seconds < 120.0) {
    std::snprintf(text, sizeof(text), "%.0f s", seconds);
  } else {
    std::snprintf(text, sizeof(text), "%.1f min", seconds / 60.0);
  }
  return text;
}

}  // namespace

bool ColmapOutputProgress::Feed(const std::string& line) {
  static const std::regex kExtracted(R"(Processed file \[(\d+)/(\d+)\])");
  static const std::regex kImage(R"(Matching image \[(\d+)/(\d+)\])");
  static const std::regex kBlock(
      R"(Matching block \[(\d+)/(\d+)(?:, (\d+)/(\d+))?\])");
  static const std::regex kRegistering(R"(Registering image #\d+ \((\d+)\))");
  static const std::regex kInitialPair(R"(Finding good initial image pair)");
  std::smatch m;
  if (std::regex_search(line, m, kExtracted) ||
      std::regex_search(line, m, kImage)) {
    what_ = line.find("Processed") != std::string::npos
                ? "extracted features of image"
                : "matching image";
    done_ = std::stoi(m[1]);
    total_ = std::stoi(m[2]);
    // Image k is done once the next one is reported: k - 1 of them.
    fraction_ = total_ > 0 ? static_cast<double>(done_ - 1) / total_ : -1.0;
    return true;
  }
  if (std::regex_search(line, m, kBlock)) {
    what_ = "matching block";
    const int outer = std::stoi(m[1]), outer_total = std::stoi(m[2]);
    int inner = 1, inner_total = 1;
    if (m[3].matched) {
      inner = std::stoi(m[3]);
      inner_total = std::stoi(m[4]);
    }
    done_ = (outer - 1) * inner_total + inner;
    total_ = outer_total * inner_total;
    fraction_ = total_ > 0 ? static_cast<double>(done_ - 1) / total_ : -1.0;
    return true;
  }
  if (std::regex_search(line, m, kRegistering)) {
    const int n = std::stoi(m[1]);
    // A smaller count: the mapper started another model.
    if (n < registered_) registered_before_ += registered_;
    registered_ = n;
    what_ = "registered";
    done_ = registered_before_ + registered_;
    total_ = num_images_;
    fraction_ = num_images_ > 0
                    ? std::min(1.0, static_cast<double>(done_) / num_images_)
                    : -1.0;
    return true;
  }
  if (std::regex_search(line, kInitialPair)) {
    what_ = "finding an initial image pair";
    return true;
  }
  return false;
}

double ColmapOutputProgress::Fraction() const { return fraction_; }

std::string ColmapOutputProgress::Describe(double elapsed_s) const {
  std::string text;
  if (what_.empty()) {
    text = "started";
  } else if (what_ == "registered") {
    text = "registered " + std::to_string(done_) +
           (total_ > 0 ? " of " + std::to_string(total_) : std::string()) +
           " images";
  } else if (what_ == "finding an initial image pair") {
    text = what_;
    if (registered_before_ + registered_ > 0) {
      text += " (" + std::to_string(registered_before_ + registered_) +
              " images registered)";
    }
  } else {
    text = what_ + " " + std::to_string(done_) + "/" + std::to_string(total_);
  }
  text += ", " + Duration(elapsed_s);
  // The time left once a tenth is done (earlier guesses jump about).
  if (fraction_ >= 0.1 && fraction_ < 1.0) {
    text += ", about " + Duration(elapsed_s * (1.0 - fraction_) / fraction_) +
            " left";
  }
  return text;
}

}  // namespace odomcal
