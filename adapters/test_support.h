// Helpers shared by the adapters' unit tests (not installed).
#pragma once

#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "odomcal/adapters/format_error.h"

namespace odomcal {

// The FormatError message thrown by `action`, or "" (and a test failure) if
// it throws none.
inline std::string FormatErrorOf(const std::function<void()>& action) {
  try {
    action();
  } catch (const FormatError& error) {
    return error.what();
  }
  ADD_FAILURE() << "no FormatError thrown";
  return "";
}

inline bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace odomcal
