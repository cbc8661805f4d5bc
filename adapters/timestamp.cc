// Exact timestamp parsing. ParseTimestampNs splits the text into sign,
// integer digits and fraction digits, and never forms a double: the integer
// part is accumulated in uint64 with overflow checks, checked against the
// plausibility limit of its unit, scaled to nanoseconds (10^9, 10^6, 10^3 or
// 1), and the first 9/6/3/0 fraction digits are added as an integer. The
// first dropped digit decides rounding (>= 5 rounds the magnitude up, i.e.
// half away from zero). The sign is applied last; the magnitude is limited to
// INT64_MAX, so INT64_MIN itself is not representable in text.
#include "odomcal/adapters/timestamp.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

namespace odomcal {
namespace {

constexpr uint64_t kInt64Max =
    static_cast<uint64_t>(std::numeric_limits<int64_t>::max());

bool IsAsciiDigit(char c) { return c >= '0' && c <= '9'; }

std::string_view TrimSpacesAndTabs(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t')) {
    text.remove_prefix(1);
  }
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) {
    text.remove_suffix(1);
  }
  return text;
}

// Number of fraction digits that are whole nanoseconds, and 10^that.
int NsFractionDigits(TimeUnit unit) {
  switch (unit) {
    case TimeUnit::kSeconds:
      return 9;
    case TimeUnit::kMilliseconds:
      return 6;
    case TimeUnit::kMicroseconds:
      return 3;
    case TimeUnit::kNanoseconds:
      return 0;
  }
  return 0;
}

uint64_t PowerOfTen(int exponent) {
  uint64_t value = 1;
  for (int i = 0; i < exponent; ++i) value *= 10;
  return value;
}

void Fail(std::string* error, std::string message) {
  if (error != nullptr) *error = std::move(message);
}

}  // namespace

TimeUnit ParseTimeUnit(const std::string& name) {
  if (name == "s") return TimeUnit::kSeconds;
  if (name == "ms") return TimeUnit::kMilliseconds;
  if (name == "us") return TimeUnit::kMicroseconds;
  if (name == "ns") return TimeUnit::kNanoseconds;
  throw std::invalid_argument(
      "time unit: expected one of s, ms, us, ns; got '" + name + "'");
}

const char* TimeUnitName(TimeUnit unit) {
  switch (unit) {
    case TimeUnit::kSeconds:
      return "s";
    case TimeUnit::kMilliseconds:
      return "ms";
    case TimeUnit::kMicroseconds:
      return "us";
    case TimeUnit::kNanoseconds:
      return "ns";
  }
  return "?";
}

std::optional<int64_t> ParseTimestampNs(std::string_view text,
                                        TimeUnit unit,
                                        std::string* error) {
  text = TrimSpacesAndTabs(text);
  const std::string quoted = "'" + std::string(text) + "'";
  if (text.empty()) {
    Fail(error, "empty timestamp");
    return std::nullopt;
  }

  size_t pos = 0;
  bool negative = false;
  if (text[pos] == '+' || text[pos] == '-') {
    negative = text[pos] == '-';
    ++pos;
  }
  const size_t integer_begin = pos;
  while (pos < text.size() && IsAsciiDigit(text[pos])) ++pos;
  const std::string_view integer_digits =
      text.substr(integer_begin, pos - integer_begin);
  std::string_view fraction_digits;
  if (pos < text.size() && text[pos] == '.') {
    const size_t fraction_begin = ++pos;
    while (pos < text.size() && IsAsciiDigit(text[pos])) ++pos;
    fraction_digits = text.substr(fraction_begin, pos - fraction_begin);
  }
  // Nanosecond logs are integers; a fraction means another unit (usually
  // seconds) was declared wrongly, which rounding would hide.
  if (unit == TimeUnit::kNanoseconds &&
      fraction_digits.find_first_not_of('0') != std::string_view::npos) {
    Fail(error,
         "timestamp " + quoted +
             " has a fractional part but the time unit is ns; pass "
             "the time unit flag");
    return std::nullopt;
  }
  if (pos < text.size() && (text[pos] == 'e' || text[pos] == 'E') &&
      !(integer_digits.empty() && fraction_digits.empty())) {
    Fail(error,
         quoted + " is not a decimal number (exponents are not supported)");
    return std::nullopt;
  }
  if (pos != text.size() ||
      (integer_digits.empty() && fraction_digits.empty())) {
    Fail(error, quoted + " is not a decimal number");
    return std::nullopt;
  }

  const std::string overflow_message =
      "timestamp " + quoted + " (" + TimeUnitName(unit) +
      ") does not fit in int64 nanoseconds (about +-292 years); is the time "
      "unit right?";
  uint64_t integer_part = 0;
  for (const char c : integer_digits) {
    const uint64_t digit = static_cast<uint64_t>(c - '0');
    if (integer_part > (kInt64Max - digit) / 10) {
      Fail(error, overflow_message);
      return std::nullopt;
    }
    integer_part = integer_part * 10 + digit;
  }

  // Checked on the integer part, before scaling, so that a nanosecond log
  // read as seconds gets this message rather than the overflow one.
  const char* unit_description = nullptr;
  if (unit == TimeUnit::kSeconds && integer_part > 100000000000ULL) {
    unit_description = "seconds";
  } else if (unit == TimeUnit::kMilliseconds &&
             integer_part > 100000000000000ULL) {
    unit_description = "milliseconds";
  }
  if (unit_description != nullptr) {
    Fail(error,
         "timestamp " + std::string(text) +
             " looks like nanoseconds or microseconds but the time unit is " +
             unit_description + "; pass the time unit flag");
    return std::nullopt;
  }

  const int kept_digits = NsFractionDigits(unit);
  const uint64_t scale = PowerOfTen(kept_digits);
  if (integer_part > kInt64Max / scale) {
    Fail(error, overflow_message);
    return std::nullopt;
  }
  uint64_t magnitude = integer_part * scale;
  uint64_t fraction_ns = 0;
  for (int i = 0; i < kept_digits; ++i) {
    const uint64_t digit = i < static_cast<int>(fraction_digits.size())
                               ? static_cast<uint64_t>(fraction_digits[i] - '0')
                               : 0;
    fraction_ns = fraction_ns * 10 + digit;
  }
  // Half away from zero: the magnitude rounds up when the first dropped
  // digit is 5 or more.
  if (static_cast<int>(fraction_digits.size()) > kept_digits &&
      fraction_digits[kept_digits] >= '5') {
    ++fraction_ns;
  }
  // magnitude <= INT64_MAX and fraction_ns <= 10^9, so this cannot wrap.
  magnitude += fraction_ns;
  if (magnitude > kInt64Max) {
    Fail(error, overflow_message);
    return std::nullopt;
  }
  const int64_t value = static_cast<int64_t>(magnitude);
  return negative ? -value : value;
}

std::string FormatTimestampSeconds(int64_t stamp_ns) {
  // Magnitude in uint64 so that INT64_MIN is formatted correctly too.
  const uint64_t magnitude = stamp_ns < 0
                                 ? static_cast<uint64_t>(-(stamp_ns + 1)) + 1
                                 : static_cast<uint64_t>(stamp_ns);
  char buffer[48];
  std::snprintf(buffer,
                sizeof(buffer),
                "%s%" PRIu64 ".%09" PRIu64,
                stamp_ns < 0 ? "-" : "",
                magnitude / uint64_t{1000000000},
                magnitude % uint64_t{1000000000});
  return buffer;
}

double NsToSeconds(int64_t stamp_ns) {
  return static_cast<double>(stamp_ns) / 1e9;
}

int64_t SecondsToNs(double seconds) {
  return static_cast<int64_t>(std::llround(seconds * 1e9));
}

double ElapsedSeconds(int64_t from_ns, int64_t to_ns) {
  return NsToSeconds(to_ns - from_ns);
}

}  // namespace odomcal
