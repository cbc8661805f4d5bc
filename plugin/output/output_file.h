// Output files of the CLI: written atomically (temporary file in the same
// folder, flushed, renamed over the target), never overwriting an existing
// file unless asked to.
#pragma once

#include <stdexcept>
#include <string>

namespace odomcal {

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws OutputError when `path` exists and !overwrite, when it exists and is
// not an odomcal result file (--overwrite replaces only odomcal's own), or
// when its folder does not exist. Call for every output before doing any work.
void CheckOutputPath(const std::string& path, bool overwrite);

// A result file odomcal wrote: JSON whose "schema" starts with "odomcal.",
// the OpenCV YAML of a calibration (%YAML:1.0, then status, message, ...,
// unobservable), or a robot file (its first line a comment naming
// kRobotOutputMarker, robot_description.h).
bool IsOdomcalResultFile(const std::string& path);

// Throws OutputError naming the path when any step fails; the target is then
// left as it was.
void WriteFileAtomically(const std::string& path, const std::string& contents);

// `path` with its extension replaced (or appended): "a/b.json" -> "a/b.yaml".
std::string ReplaceExtension(const std::string& path,
                             const std::string& extension);

}  // namespace odomcal
