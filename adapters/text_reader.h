// Line-oriented text input shared by the COLMAP text model and image
// timestamp readers: a line reader that counts 1-based line numbers, field
// splitting, and locale-independent number parsing.
//
// Every failure throws FormatError with "path:line: what", the format of
// format_error.h. Number parsing uses std::from_chars (never strtod, whose
// decimal point depends on the C locale) and rejects anything that is not
// consumed completely, so "1.5x" or "" never pass as numbers.
#pragma once

#include "odomcal/adapters/format_error.h"

#include <cstdint>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace odomcal {

class TextLineReader {
 public:
  // Opens `path`. Throws FormatError "path: cannot open for reading: <why>"
  // when it is missing, a directory or unreadable.
  explicit TextLineReader(const std::string& path);

  // Next line without its line terminator ('\n' or "\r\n") and, on the
  // first line, without a UTF-8 byte order mark, whatever it holds (blank
  // lines and comments included). Returns false at the end of
  // the file; throws FormatError on a read error.
  bool NextRawLine(std::string* line);

  // Next line that is neither blank (spaces and tabs only) nor a comment
  // (first non-blank character '#'). Returns false at the end of the file.
  bool NextDataLine(std::string* line);

  // 1-based number of the line returned last (0 before the first).
  int line_number() const { return line_number_; }
  const std::string& path() const { return path_; }

  // Throws FormatError "path:line: what" for the line returned last.
  [[noreturn]] void Fail(const std::string& what) const;

 private:
  std::string path_;
  std::ifstream stream_;
  int line_number_ = 0;
};

// Removes a UTF-8 byte order mark (EF BB BF) at the start of `line`, as
// some Windows editors write before the first line of a text file.
void StripUtf8Bom(std::string* line);

// `text` without leading and trailing spaces, tabs and carriage returns.
std::string_view TrimBlanks(std::string_view text);

// Fields separated by runs of spaces or tabs (none for a blank line).
std::vector<std::string_view> SplitOnBlanks(std::string_view line);

// Fields separated by commas, each trimmed of blanks; empty fields are kept
// ("a,,b" gives three fields) so that they can be reported.
std::vector<std::string_view> SplitOnCommas(std::string_view line);

// Parsers for one whole field. On failure they call reader.Fail() with a
// message naming `what` and the offending text, e.g.
//   "path:3: QW: 'abc' is not a number".
// ParseFiniteDouble also rejects "nan", "inf" and values that overflow.
double ParseFiniteDouble(std::string_view field,
                         const char* what,
                         const TextLineReader& reader);
// Decimal digits only (no sign), at most `max_value`.
uint64_t ParseUnsigned(std::string_view field,
                       const char* what,
                       uint64_t max_value,
                       const TextLineReader& reader);

}  // namespace odomcal
