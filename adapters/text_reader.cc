// A std::ifstream read with std::getline; the line counter advances on every
// physical line so that messages point at the line a user sees in an editor.
// Numbers go through std::from_chars over the whole field.
#include "odomcal/adapters/text_reader.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <system_error>

namespace odomcal {

TextLineReader::TextLineReader(const std::string& path) : path_(path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) {
    throw FormatError(path + ": cannot open for reading: is a directory");
  }
  errno = 0;
  stream_.open(path, std::ios::binary);
  if (!stream_.is_open()) {
    const std::string reason =
        errno != 0 ? std::string(": ") + std::strerror(errno) : std::string();
    throw FormatError(path + ": cannot open for reading" + reason);
  }
}

bool TextLineReader::NextRawLine(std::string* line) {
  if (std::getline(stream_, *line)) {
    ++line_number_;
    if (line_number_ == 1) StripUtf8Bom(line);
    if (!line->empty() && line->back() == '\r') line->pop_back();
    return true;
  }
  if (stream_.bad()) {
    throw FormatError(path_ + ":" + std::to_string(line_number_ + 1) +
                      ": read error");
  }
  return false;
}

bool TextLineReader::NextDataLine(std::string* line) {
  while (NextRawLine(line)) {
    const std::string_view trimmed = TrimBlanks(*line);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    return true;
  }
  return false;
}

void TextLineReader::Fail(const std::string& what) const {
  throw FormatError(path_ + ":" + std::to_string(line_number_) + ": " + what);
}

void StripUtf8Bom(std::string* line) {
  if (line->compare(0, 3, "\xEF\xBB\xBF") == 0) line->erase(0, 3);
}

std::string_view TrimBlanks(std::string_view text) {
  const size_t first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const size_t last = text.find_last_not_of(" \t\r");
  return text.substr(first, last - first + 1);
}

std::vector<std::string_view> SplitOnBlanks(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t pos = 0;
  while (true) {
    const size_t begin = line.find_first_not_of(" \t\r", pos);
    if (begin == std::string_view::npos) break;
    const size_t end = line.find_first_of(" \t\r", begin);
    fields.push_back(line.substr(begin, end - begin));
    if (end == std::string_view::npos) break;
    pos = end;
  }
  return fields;
}

std::vector<std::string_view> SplitOnCommas(std::string_view line) {
  std::vector<std::string_view> fields;
  size_t begin = 0;
  while (true) {
    const size_t comma = line.find(',', begin);
    fields.push_back(TrimBlanks(line.substr(begin, comma - begin)));
    if (comma == std::string_view::npos) break;
    begin = comma + 1;
  }
  return fields;
}

double ParseFiniteDouble(std::string_view field,
                         const char* what,
                         const TextLineReader& reader) {
  double value = 0.0;
  const char* const end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  if (field.empty() || ec == std::errc::invalid_argument || ptr != end) {
    reader.Fail(std::string(what) + ": '" + std::string(field) +
                "' is not a number");
  }
  if (ec == std::errc::result_out_of_range || !std::isfinite(value)) {
    reader.Fail(std::string(what) + ": '" + std::string(field) +
                "' is not a finite number");
  }
  return value;
}

uint64_t ParseUnsigned(std::string_view field,
                       const char* what,
                       uint64_t max_value,
                       const TextLineReader& reader) {
  uint64_t value = 0;
  const char* const end = field.data() + field.size();
  const auto [ptr, ec] = std::from_chars(field.data(), end, value);
  if (field.empty() || field.front() == '-' ||
      ec == std::errc::invalid_argument || ptr != end) {
    reader.Fail(std::string(what) + ": '" + std::string(field) +
                "' is not a non-negative integer");
  }
  if (ec == std::errc::result_out_of_range || value > max_value) {
    reader.Fail(std::string(what) + ": " + std::string(field) +
                " is out of range (largest accepted: " +
                std::to_string(max_value) + ")");
  }
  return value;
}

}  // namespace odomcal
