// Capture times of images, looked up by image name (COLMAP's image name: the
// path relative to the image folder, '/'-separated, e.g. "cam0/000123.png").
//
// Two sources:
//
// 1. A CSV file, one image per line: `image_name,timestamp`.
//    - Keys are the FULL relative names, compared exactly (case-sensitive, no
//      "./" or '\\' normalisation): "cam0/000123.png" and "000123.png" are
//      different images.
//    - Timestamps are decimal numbers in seconds unless another TimeUnit is
//      given, parsed exactly by ParseTimestampNs (no exponents, no nan/inf).
//    - The first data line is a header, and skipped, when its timestamp field
//      holds no digit (e.g. "image_name,timestamp"); a field with digits that
//      does not parse ("1e9"), "nan" or "inf" is an error, even on the first
//      line. Blank lines and lines
//      starting with '#' are skipped. Fields are trimmed of blanks and of
//      one pair of enclosing double quotes ("000001.png" as a spreadsheet
//      writes it, also in the header); names cannot contain commas. A UTF-8
//      byte order mark before the first line is ignored.
//    - Errors (FormatError, "path:line: what"): not exactly two fields, an
//      empty name, a bad timestamp, a name listed twice (both lines named),
//      no data lines.
//
// 2. The image file names. The rule, applied to the BASE name (the part after
//    the last '/', so "cam0/1403636579763555584.png" works):
//    - the extension is removed: the text from the last '.' when it contains
//      a character other than a digit ("x.png" -> "x", but "1.5" stays);
//    - the rest (the stem) must be `DIGITS` or `DIGITS.DIGITS`;
//    - an integer stem is read in nanoseconds, a stem with a decimal point
//      in seconds, unless a TimeUnit is given, which then applies to both:
//        1403636579763555584.png  -> 1403636579763555584 ns
//        1403636579.763555.png    -> 1403636579763555000 ns
//        cam0/000123.png          -> 123 ns (frame numbers are NOT times:
//                                    use a CSV for such names; the
//                                    calibration refuses image times less
//                                    than 1 ms apart, input_plausibility.h)
//    - names that do not follow the rule have no timestamp; the lookup says
//      why.
//
// A constant offset between the camera clock and the odometry clock is not
// applied here: see AssociationOptions::camera_time_offset_ns.
#pragma once

#include "odomcal/adapters/timestamp.h"

#include <cstdint>
#include <map>
#include <optional>
#include <string>

namespace odomcal {

// Reads a CSV of `image_name,timestamp` lines (see the top of this file).
// Returns image name -> stamp in nanoseconds.
std::map<std::string, int64_t> ReadImageTimestampsCsv(const std::string& path,
                                                      TimeUnit unit);

// The file-name rule (see the top of this file). `unit` overrides the unit
// chosen from the stem's form. Returns std::nullopt and sets *error (when not
// null) to a one-line reason when the name does not follow the rule or the
// number is out of range.
std::optional<int64_t> TimestampFromImageName(const std::string& image_name,
                                              std::optional<TimeUnit> unit,
                                              std::string* error);

// One of the two sources, behind a single lookup.
class ImageTimestamps {
 public:
  // Lookup in ReadImageTimestampsCsv(path, unit). Throws as that does.
  static ImageTimestamps FromCsv(const std::string& path, TimeUnit unit);
  // Lookup by TimestampFromImageName(name, unit).
  static ImageTimestamps FromFileNames(std::optional<TimeUnit> unit);
  // Lookup in a given table (e.g. built by the caller or a test).
  static ImageTimestamps FromTable(std::map<std::string, int64_t> table,
                                   std::string source);

  // The stamp of `image_name` in nanoseconds, or std::nullopt with *why (when
  // not null) set to a one-line reason, e.g.
  //   "'a.png' is not listed in stamps.csv".
  std::optional<int64_t> Lookup(const std::string& image_name,
                                std::string* why) const;

  // Where the stamps come from, for messages: the CSV path, or
  // "image file names".
  const std::string& source() const { return source_; }

  // How the stamps were obtained, for messages: "read from the image names
  // as ns (s for names with a decimal point)", "read from the image names as
  // ms", "read from stamps.csv in s".
  const std::string& how_read() const { return how_read_; }

 private:
  ImageTimestamps() = default;

  bool from_file_names_ = false;
  std::optional<TimeUnit> file_name_unit_;
  std::map<std::string, int64_t> table_;
  std::string source_;
  std::string how_read_;
};

}  // namespace odomcal
