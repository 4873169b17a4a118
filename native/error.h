#pragma once
#include <stdexcept>
#include <string>

namespace rtsdf {

// Every failure the user can cause or meet (bad input, no device, out of
// memory) is thrown as an Error with a one-line message meant for them.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace rtsdf
