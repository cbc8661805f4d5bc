#include "odomcal/plugin/output/output_guard.h"

#include "odomcal/plugin/output/output_file.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

// A path as written (absolute, "." and ".." removed) and as the file system
// resolves it.
struct ResolvedPath {
  fs::path lexical;
  fs::path real;  // symbolic links resolved, as far as the path exists
  bool exists = false;
  bool is_folder = false;
  dev_t device = 0;
  ino_t inode = 0;
};

// "a/b/" -> "a/b": a trailing separator would make an empty last component.
fs::path WithoutTrailingSeparator(fs::path path) {
  if (!path.has_filename() && path.has_parent_path() &&
      path != path.root_path()) {
    path = path.parent_path();
  }
  return path;
}

ResolvedPath Resolve(const std::string& path) {
  std::error_code error;
  ResolvedPath resolved;
  resolved.lexical =
      WithoutTrailingSeparator(fs::absolute(path, error).lexically_normal());
  resolved.real = fs::weakly_canonical(resolved.lexical, error);
  resolved.real =
      error ? resolved.lexical : WithoutTrailingSeparator(resolved.real);
  struct stat status;
  if (::stat(path.c_str(), &status) == 0) {
    resolved.exists = true;
    resolved.is_folder = S_ISDIR(status.st_mode);
    resolved.device = status.st_dev;
    resolved.inode = status.st_ino;
  }
  return resolved;
}

// How `a` is the same file as `b`, for the message; "" when it is not.
std::string SameFileRelation(const ResolvedPath& a, const ResolvedPath& b) {
  if (a.lexical == b.lexical) return "is";
  if (a.real == b.real) return "resolves through a symbolic link to";
  if (a.exists && b.exists && a.device == b.device && a.inode == b.inode) {
    return "is a hard link to";
  }
  return "";
}

// `inner` lies strictly below folder `outer` (both real paths).
bool IsInside(const fs::path& inner, const fs::path& outer) {
  const auto mismatch =
      std::mismatch(outer.begin(), outer.end(), inner.begin(), inner.end());
  return mismatch.first == outer.end() && mismatch.second != inner.end();
}

std::string Named(const FlaggedPath& path) {
  return path.path + " (" + path.flag + ")";
}

struct ResolvedOutput {
  FlaggedPath named;
  ResolvedPath resolved;
  bool is_folder = false;
};

}  // namespace

void CheckOutputsApartFromInputs(const GuardedPaths& paths) {
  std::vector<std::pair<FlaggedPath, ResolvedPath>> inputs;
  for (const FlaggedPath& input : paths.inputs) {
    if (!input.path.empty()) inputs.emplace_back(input, Resolve(input.path));
  }
  std::vector<ResolvedOutput> outputs;
  for (const FlaggedPath& file : paths.output_files) {
    outputs.push_back({file, Resolve(file.path), false});
  }
  for (const FlaggedPath& folder : paths.output_folders) {
    outputs.push_back({folder, Resolve(folder.path), true});
  }

  for (size_t k = 0; k < outputs.size(); ++k) {
    const ResolvedOutput& output = outputs[k];
    for (const auto& [input, resolved] : inputs) {
      const std::string relation = SameFileRelation(output.resolved, resolved);
      if (!relation.empty()) {
        throw OutputError(Named(output.named) + " " + relation + " the input " +
                          Named(input) +
                          "; odomcal never writes over an input");
      }
      if (resolved.is_folder && IsInside(output.resolved.real, resolved.real)) {
        throw OutputError(Named(output.named) + " is inside the input folder " +
                          Named(input) +
                          "; odomcal never writes into an input");
      }
      if (output.is_folder && IsInside(resolved.real, output.resolved.real)) {
        throw OutputError(
            Named(output.named) + " holds the input " + Named(input) +
            "; odomcal never writes into a folder that holds an input");
      }
    }
    for (size_t j = 0; j < k; ++j) {
      const std::string relation =
          SameFileRelation(output.resolved, outputs[j].resolved);
      if (!relation.empty()) {
        throw OutputError(Named(output.named) + " " + relation +
                          " the output " + Named(outputs[j].named) +
                          "; two outputs cannot share a file");
      }
    }
  }
}

}  // namespace odomcal
