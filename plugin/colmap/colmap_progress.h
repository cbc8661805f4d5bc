// What a running COLMAP stage has done so far, read from the lines it prints
// (COLMAP 3.8; 3.9-3.12 print the same): "Processed file [12/300]"
// (feature_extractor), "Matching image [120/300]" (sequential and spatial
// matchers), "Matching block [2/5]" or "[1/3, 2/3]" (matches_importer,
// exhaustive), "Registering image #57 (85)" (mapper: the 85th image of the
// model being built). Lines that say nothing of progress are ignored, so
// that glog prefixes, headings and other versions' lines are harmless.
#pragma once

#include <string>

namespace odomcal {

class ColmapOutputProgress {
 public:
  // num_images: images the stage works on (the mapper's fraction); 0 if
  // unknown.
  explicit ColmapOutputProgress(int num_images = 0) : num_images_(num_images) {}

  // One line of output (with or without its end of line); true when it
  // changed the progress.
  bool Feed(const std::string& line);

  // Of the stage, in [0, 1]; negative while unknown.
  double Fraction() const;

  // "matching image 120/300, 45 s, about 68 s left", "registered 85 of 300
  // images, 30 s": the last progress line and the time since the stage
  // started; the time left is extrapolated from the fraction done.
  std::string Describe(double elapsed_s) const;

 private:
  int num_images_ = 0;
  std::string what_;  // "" until a line told progress
  int done_ = 0;
  int total_ = 0;
  double fraction_ = -1.0;
  // Mapper: images registered in finished models, and in the current one.
  int registered_before_ = 0;
  int registered_ = 0;
};

}  // namespace odomcal
