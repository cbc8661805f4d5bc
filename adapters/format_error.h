// The exception type for unreadable or malformed input files.
//
// Every reader and writer in adapters/ reports I/O and parse problems by
// throwing FormatError. Its what() is a single line that starts with the file
// path and, when the problem sits on a line, its 1-based line number:
//   "poses.tum:12: expected 8 fields (timestamp tx ty tz qx qy qz qw), got 7"
//   "poses.tum: cannot open for reading: No such file or directory"
// so the command-line tool can print it as is (and exit with status 2).
// Invalid arguments (an unknown format name, a negative threshold) are not
// FormatErrors; they throw std::invalid_argument.
#pragma once

#include <stdexcept>

namespace odomcal {

class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace odomcal
