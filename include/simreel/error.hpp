// Bad input found while building a model (a mesh that is open, a negative mass, ...). Loaders
// catch it and add where the input came from (file, line, key); the CLI maps it to exit code 2.
#pragma once
#include <stdexcept>
#include <string>

namespace simreel {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A non-finite value appeared in the state while stepping: the message names the body and the time.
class StateError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace simreel
