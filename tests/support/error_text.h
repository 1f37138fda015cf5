#pragma once
// The message of the relume::Error a call throws, for tests of error messages.
#include <functional>
#include <string>

#include "relume/geometry/error.h"

namespace relume::test {

// What `call` throws as relume::Error ("" when it throws none; other exceptions pass through).
inline std::string errorText(const std::function<void()>& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace relume::test
