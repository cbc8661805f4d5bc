// Fuzzes ReadOdometryCsv (timestamp,x,y,yaw): the input is written to a
// scratch file and read in every TimeUnit; then ReadOdometry with
// OdometryFormat::kAuto, whose format sniffing reads the first data line.
//
// Expected outcome for malformed input: FormatError. Anything else (a crash,
// a sanitizer report, any other exception) escapes and is a finding.
#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/trajectory_io.h"

#include "scratch_dir.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const odomcal::ScratchDir scratch;
  const std::string path =
      scratch.Write("odometry.csv", odomcal::AsBytes(data, size));
  for (const odomcal::TimeUnit unit : {odomcal::TimeUnit::kSeconds,
                                       odomcal::TimeUnit::kMilliseconds,
                                       odomcal::TimeUnit::kMicroseconds,
                                       odomcal::TimeUnit::kNanoseconds}) {
    try {
      odomcal::ReadOdometryCsv(path, unit);
    } catch (const odomcal::FormatError&) {
    }
  }
  // No extension that decides the format, so the content does.
  const std::string unnamed_path =
      scratch.Write("odometry", odomcal::AsBytes(data, size));
  try {
    odomcal::ReadOdometry(unnamed_path,
                          odomcal::OdometryFormat::kAuto,
                          odomcal::TimeUnit::kSeconds);
  } catch (const odomcal::FormatError&) {
  }
  return 0;
}
