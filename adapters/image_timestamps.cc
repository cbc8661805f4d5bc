// The CSV reader goes line by line through TextLineReader, splits on commas
// and hands the timestamp field to the exact ParseTimestampNs; the name ->
// line map detects duplicates. The file-name rule strips the directory and
// the extension, checks the stem's grammar, then also uses ParseTimestampNs,
// so both sources round the same way and share its plausibility guard.
#include "odomcal/adapters/image_timestamps.h"

#include "odomcal/adapters/format_error.h"
#include "odomcal/adapters/text_reader.h"

#include <algorithm>
#include <cctype>
#include <string_view>
#include <utility>
#include <vector>

namespace odomcal {
namespace {

bool IsDigit(char c) {
  return std::isdigit(static_cast<unsigned char>(c)) != 0;
}

bool AllDigits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), IsDigit);
}

// A header names its columns: no digit in the timestamp field, and not one
// of the non-finite spellings that are data errors.
bool LooksLikeHeader(std::string_view field) {
  if (std::any_of(field.begin(), field.end(), IsDigit)) return false;
  if (!field.empty() && (field.front() == '+' || field.front() == '-')) {
    field.remove_prefix(1);
  }
  std::string lower;
  for (const char c : field) {
    lower.push_back(
        static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return lower != "nan" && lower != "inf" && lower != "infinity";
}

// `field` without one pair of enclosing double quotes, as spreadsheet
// programs write text fields.
std::string_view Unquoted(std::string_view field) {
  if (field.size() >= 2 && field.front() == '"' && field.back() == '"') {
    return TrimBlanks(field.substr(1, field.size() - 2));
  }
  return field;
}

}  // namespace

std::map<std::string, int64_t> ReadImageTimestampsCsv(const std::string& path,
                                                      TimeUnit unit) {
  TextLineReader reader(path);
  std::map<std::string, int64_t> stamps;
  std::map<std::string, int> line_of_name;
  std::string line;
  bool first = true;
  while (reader.NextDataLine(&line)) {
    std::vector<std::string_view> fields = SplitOnCommas(line);
    for (std::string_view& field : fields) field = Unquoted(field);
    if (fields.size() != 2) {
      reader.Fail(
          "expected 2 comma-separated fields (image_name,timestamp), "
          "got " +
          std::to_string(fields.size()));
    }
    std::string error;
    const std::optional<int64_t> stamp_ns =
        ParseTimestampNs(fields[1], unit, &error);
    if (!stamp_ns) {
      if (first && LooksLikeHeader(fields[1])) {
        first = false;
        continue;
      }
      reader.Fail("timestamp of '" + std::string(fields[0]) + "': " + error);
    }
    first = false;
    if (fields[0].empty()) reader.Fail("empty image name");
    const std::string name(fields[0]);
    const auto [it, inserted] =
        line_of_name.emplace(name, reader.line_number());
    if (!inserted) {
      reader.Fail("image '" + name + "' is listed twice (first on line " +
                  std::to_string(it->second) + ")");
    }
    stamps.emplace(name, *stamp_ns);
  }
  if (stamps.empty()) {
    throw FormatError(path + ": no image timestamps (" +
                      std::to_string(reader.line_number()) +
                      " lines, none with image_name,timestamp)");
  }
  return stamps;
}

std::optional<int64_t> TimestampFromImageName(const std::string& image_name,
                                              std::optional<TimeUnit> unit,
                                              std::string* error) {
  const auto fail = [&](const std::string& why) -> std::optional<int64_t> {
    if (error != nullptr) {
      *error = "image name '" + image_name + "': " + why;
    }
    return std::nullopt;
  };
  std::string_view stem = image_name;
  const size_t slash = stem.rfind('/');
  if (slash != std::string_view::npos) stem.remove_prefix(slash + 1);
  const size_t dot = stem.rfind('.');
  if (dot != std::string_view::npos && !AllDigits(stem.substr(dot + 1))) {
    stem = stem.substr(0, dot);
  }
  const size_t point = stem.find('.');
  const bool is_integer = AllDigits(stem);
  const bool is_decimal = point != std::string_view::npos &&
                          AllDigits(stem.substr(0, point)) &&
                          AllDigits(stem.substr(point + 1));
  if (!is_integer && !is_decimal) {
    return fail(
        "the file name is not a time (expected DIGITS or "
        "DIGITS.DIGITS before the extension, e.g. "
        "1403636579763555584.png or 1403636579.763555.png)");
  }
  const TimeUnit stem_unit =
      unit ? *unit : (is_integer ? TimeUnit::kNanoseconds : TimeUnit::kSeconds);
  std::string parse_error;
  const std::optional<int64_t> stamp_ns =
      ParseTimestampNs(stem, stem_unit, &parse_error);
  if (!stamp_ns) return fail(parse_error);
  return stamp_ns;
}

ImageTimestamps ImageTimestamps::FromCsv(const std::string& path,
                                         TimeUnit unit) {
  ImageTimestamps timestamps =
      FromTable(ReadImageTimestampsCsv(path, unit), path);
  timestamps.how_read_ =
      std::string("read from ") + path + " in " + TimeUnitName(unit);
  return timestamps;
}

ImageTimestamps ImageTimestamps::FromFileNames(std::optional<TimeUnit> unit) {
  ImageTimestamps timestamps;
  timestamps.from_file_names_ = true;
  timestamps.file_name_unit_ = unit;
  timestamps.source_ = "image file names";
  timestamps.how_read_ =
      unit ? std::string("read from the image names as ") + TimeUnitName(*unit)
           : "read from the image names as ns (s for names with a decimal "
             "point)";
  return timestamps;
}

ImageTimestamps ImageTimestamps::FromTable(std::map<std::string, int64_t> table,
                                           std::string source) {
  ImageTimestamps timestamps;
  timestamps.table_ = std::move(table);
  timestamps.how_read_ = "read from " + source;
  timestamps.source_ = std::move(source);
  return timestamps;
}

std::optional<int64_t> ImageTimestamps::Lookup(const std::string& image_name,
                                               std::string* why) const {
  if (from_file_names_) {
    return TimestampFromImageName(image_name, file_name_unit_, why);
  }
  const auto it = table_.find(image_name);
  if (it == table_.end()) {
    if (why != nullptr) {
      *why = "'" + image_name + "' is not listed in " + source_;
    }
    return std::nullopt;
  }
  return it->second;
}

}  // namespace odomcal
