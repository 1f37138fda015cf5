#include "relume/geometry/error.h"

namespace relume {

namespace {
std::string compose(const std::string& file, const std::string& element, const std::string& problem) {
  std::string s;
  if (!file.empty()) s += file + ": ";
  if (!element.empty()) s += element + ": ";
  return s + problem;
}
}  // namespace

Error::Error(std::string file, std::string element, std::string problem)
    : std::runtime_error(compose(file, element, problem)),
      file_(std::move(file)),
      element_(std::move(element)),
      problem_(std::move(problem)) {}

}  // namespace relume
