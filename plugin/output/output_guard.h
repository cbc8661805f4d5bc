// The rule that an output never touches an input: every command that writes
// calls CheckOutputsApartFromInputs before doing any work. Paths are compared
// as the file system sees them: real paths after symbolic links, and device
// and inode, so that a hard link of an input counts as that input.
#pragma once

#include <string>
#include <vector>

namespace odomcal {

// A path with the flag that named it, for the error message: {"odometry.csv",
// "--odometry"}, or {"result.yaml", "the YAML beside --output"}.
struct FlaggedPath {
  std::string path;
  std::string flag;
};

struct GuardedPaths {
  std::vector<FlaggedPath> inputs;  // files or folders; empty paths skipped
  std::vector<FlaggedPath> output_files;    // written or replaced
  std::vector<FlaggedPath> output_folders;  // written into
};

// Throws OutputError, naming both paths and both flags, when an output
// resolves to an input or to another output, when an output lies inside an
// input folder, or when an input lies inside an output folder.
void CheckOutputsApartFromInputs(const GuardedPaths& paths);

}  // namespace odomcal
