// Output folders and the rule of --overwrite: odomcal replaces or removes
// only what it wrote itself. Every output folder keeps a record,
// `.odomcal_outputs`, of the entries odomcal writes directly in it (files and
// sub-folders, one name a line); an entry that exists but is not recorded is
// the user's (say COLMAP's project.ini) and is never replaced or removed.
#pragma once

#include <string>
#include <vector>

namespace odomcal {

inline constexpr char kOutputRecordName[] = ".odomcal_outputs";

// What an existing output folder may already hold.
enum class ExistingOutputs {
  kRefuseNonEmptyFolder,  // anything (but the record): refused; no --overwrite
  kRefuseExistingEntry,   // an entry odomcal is about to write: refused
  kReplaceOwn,            // odomcal's own entries: --overwrite, and reruns
};

// Creates `folder` if needed and checks that odomcal may write each of
// `entries` (names directly in `folder`), then adds them to its record, all
// before any work is done. Throws OutputError when `folder` is not a folder
// or cannot be created, when `existing` refuses what is there, or when an
// entry exists that the record does not list.
void ClaimOutputFolder(const std::string& folder,
                       const std::vector<std::string>& entries,
                       ExistingOutputs existing);

// Removes `folder`/`relative` (a file, or a folder with everything in it)
// when the record of `folder` lists the first component of `relative`;
// throws OutputError otherwise. A missing entry is not an error.
void RemoveOwnedOutput(const std::string& folder, const std::string& relative);

}  // namespace odomcal
