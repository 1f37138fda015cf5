#include "process_exit.h"

#include <cstdio>
#include <cstdlib>

namespace relume {

void endProcess(int code) {
  std::fflush(nullptr);
  std::quick_exit(code);
}

}  // namespace relume
