#pragma once
// A file's text with one change, for tests of malformed inputs.
#include <gtest/gtest.h>

#include <string>

namespace relume::test {

// `base` with its first `from` replaced by `to` (a failed expectation when `from` is not there).
inline std::string replaced(const std::string& base, const std::string& from, const std::string& to) {
  std::string s = base;
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

}  // namespace relume::test
