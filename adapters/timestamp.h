// Timestamps: exact decimal parsing into int64 nanoseconds, and back.
//
// Time is int64_t nanoseconds everywhere in odomcal (about +-292 years around
// the epoch). A double holds integers exactly only up to 2^53, so a Unix time
// in nanoseconds (~1.7e18) does not survive a trip through double: parsing
// here works on the decimal digits, and durations are formed by subtracting
// the integers first and converting the (small) difference afterwards.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace odomcal {

// Unit of the numbers in a timestamp column.
enum class TimeUnit { kSeconds, kMilliseconds, kMicroseconds, kNanoseconds };

// "s", "ms", "us" or "ns". Throws std::invalid_argument naming the accepted
// names for anything else.
TimeUnit ParseTimeUnit(const std::string& name);

// The short name accepted by ParseTimeUnit ("s", "ms", "us", "ns").
const char* TimeUnitName(TimeUnit unit);

// Parses a decimal number of `unit`s into nanoseconds, exactly.
//
// Grammar: optional sign ('+' or '-'), digits, optional '.', digits; at least
// one digit overall ("5", "-1.25", ".5", "5." are accepted). Surrounding
// spaces and tabs are ignored. Exponents ("1e9"), hexadecimal, "nan", "inf",
// and anything else are rejected.
//
// Fraction digits finer than one nanosecond (more than 9 for seconds, 6 for
// milliseconds, 3 for microseconds, any for nanoseconds) are ROUNDED HALF
// AWAY FROM ZERO: "0.0000000005" s -> 1 ns, "-0.0000000005" s -> -1 ns,
// "2.4" ns -> 2 ns.
//
// Plausibility guard: a seconds value with magnitude above 1e11 (year ~5100)
// or a milliseconds value above 1e14 is almost certainly a log in micro- or
// nanoseconds read with the wrong unit, and is refused with a message saying
// so ("... pass the time unit flag"). The int64 range ends at about 9.2e9 s,
// so seconds values between that and 1e11 fail as out of range instead.
//
// Returns std::nullopt on any failure, including results outside the int64
// range, and then sets *error (when error is not null) to a one-line reason
// without a trailing period, e.g. "'1e9' is not a decimal number (exponents
// are not supported)". On success *error is left unchanged.
std::optional<int64_t> ParseTimestampNs(std::string_view text,
                                        TimeUnit unit,
                                        std::string* error);

// Exact decimal seconds with 9 fraction digits, e.g. -1500000000 ->
// "-1.500000000". ParseTimestampNs(FormatTimestampSeconds(ns), kSeconds)
// gives ns back, except for values beyond the plausibility guard (1e11 s).
std::string FormatTimestampSeconds(int64_t stamp_ns);

// stamp_ns / 1e9, the nearest double. Loses sub-microsecond precision for
// Unix times; prefer ElapsedSeconds for durations.
double NsToSeconds(int64_t stamp_ns);

// A duration in seconds to the nearest nanosecond (half away from zero).
// Precondition: |seconds| < 9.2e9, so the result fits in int64.
int64_t SecondsToNs(double seconds);

// (to_ns - from_ns) in seconds. The subtraction is done in integers, so the
// result is exact to double precision even for nearby Unix times in ns.
// Precondition: the difference fits in int64 (stamps within ~292 years).
double ElapsedSeconds(int64_t from_ns, int64_t to_ns);

}  // namespace odomcal
