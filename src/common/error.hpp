// Errors that reach the user. InputError is for bad input (deck, mesh, options): its
// message names the file, the key or the element, and the reason. SolveError is for a
// run that started well and then failed (divergence, inverted element): its message names
// the step and the cause. main() prints either and exits without writing results.
#pragma once

#include <stdexcept>
#include <string>

namespace hs {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SolveError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace hs
