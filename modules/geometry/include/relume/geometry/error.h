#pragma once
// The one error type of Relume: which file, which element, and what is wrong, in plain words.
#include <stdexcept>
#include <string>

namespace relume {

class Error : public std::runtime_error {
 public:
  Error(std::string file, std::string element, std::string problem);

  const std::string& file() const { return file_; }
  const std::string& element() const { return element_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string file_, element_, problem_;
};

// Thrown when the user cancels a long step; nothing half-done is kept.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace relume
