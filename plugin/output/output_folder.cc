#include "odomcal/plugin/output/output_folder.h"

#include "odomcal/plugin/output/output_file.h"

#include <filesystem>
#include <fstream>
#include <set>

namespace odomcal {
namespace {

namespace fs = std::filesystem;

std::set<std::string> ReadRecord(const fs::path& folder) {
  std::set<std::string> names;
  std::ifstream record(folder / kOutputRecordName);
  std::string line;
  while (std::getline(record, line)) {
    if (!line.empty() && line[0] != '#') names.insert(line);
  }
  return names;
}

void WriteRecord(const fs::path& folder, const std::set<std::string>& names) {
  std::string text =
      "# The entries of this folder that odomcal wrote: odomcal --overwrite "
      "replaces or removes only these.\n";
  for (const std::string& name : names) text += name + "\n";
  WriteFileAtomically((folder / kOutputRecordName).string(), text);
}

bool HoldsMoreThanTheRecord(const fs::path& folder) {
  std::error_code error;
  for (fs::directory_iterator it(folder, error), end; !error && it != end;
       it.increment(error)) {
    if (it->path().filename() != kOutputRecordName) return true;
  }
  return false;
}

std::string ForeignEntryMessage(const fs::path& folder,
                                const std::string& entry) {
  return (folder / entry).string() +
         ": was not written by odomcal (not listed in " +
         (folder / kOutputRecordName).string() +
         "); --overwrite replaces only odomcal's own files";
}

}  // namespace

void ClaimOutputFolder(const std::string& folder_name,
                       const std::vector<std::string>& entries,
                       ExistingOutputs existing) {
  const fs::path folder(folder_name);
  std::error_code error;
  if (fs::exists(folder, error) && !fs::is_directory(folder, error)) {
    throw OutputError(folder_name + ": exists and is not a folder");
  }
  if (existing == ExistingOutputs::kRefuseNonEmptyFolder &&
      fs::is_directory(folder, error) && HoldsMoreThanTheRecord(folder)) {
    throw OutputError(
        folder_name +
        ": is not empty (pass --overwrite to replace odomcal's files in it)");
  }
  std::set<std::string> record = ReadRecord(folder);
  for (const std::string& entry : entries) {
    if (!fs::exists(fs::symlink_status(folder / entry, error))) continue;
    if (existing == ExistingOutputs::kRefuseExistingEntry) {
      throw OutputError((folder / entry).string() +
                        ": exists (pass --overwrite to replace it)");
    }
    if (record.count(entry) == 0)
      throw OutputError(ForeignEntryMessage(folder, entry));
  }
  fs::create_directories(folder, error);
  if (error) {
    throw OutputError(folder_name + ": cannot create (" + error.message() +
                      ")");
  }
  const size_t num_recorded = record.size();
  record.insert(entries.begin(), entries.end());
  if (record.size() != num_recorded ||
      !fs::exists(folder / kOutputRecordName)) {
    WriteRecord(folder, record);
  }
}

void RemoveOwnedOutput(const std::string& folder_name,
                       const std::string& relative) {
  const fs::path folder(folder_name);
  const fs::path target = folder / relative;
  std::error_code error;
  if (!fs::exists(fs::symlink_status(target, error))) return;
  const std::string entry = fs::path(relative).begin()->string();
  if (ReadRecord(folder).count(entry) == 0) {
    throw OutputError(ForeignEntryMessage(folder, entry));
  }
  fs::remove_all(target, error);
  if (error) {
    throw OutputError(target.string() + ": cannot remove (" + error.message() +
                      ")");
  }
}

}  // namespace odomcal
