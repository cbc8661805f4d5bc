// Fuzzes the COLMAP database reader: the input is written to a scratch file
// database.db, which ReadColmapDatabaseImages and ReadColmapDatabaseCameras
// then open read-only (immutable) through SQLite, as on a user's project.
//
// Expected outcome for malformed input: FormatError (not a database, missing
// tables, wrong column types, bad blobs). Anything else (a crash, a sanitizer
// report, any other exception) escapes and is a finding.
#include "odomcal/adapters/colmap_database.h"
#include "odomcal/adapters/format_error.h"

#include "scratch_dir.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const std::string path =
      scratch.Write("database.db", odomcal::AsBytes(data, size));
  try {
    odomcal::ReadColmapDatabaseImages(path);
  } catch (const odomcal::FormatError&) {
  }
  try {
    odomcal::ReadColmapDatabaseCameras(path);
  } catch (const odomcal::FormatError&) {
  }
  return 0;
}
