// Errors that reach the user. InputError is for bad input (deck, mesh, options): its
// message names the file, the key or the element, and the reason. SolveError is for a
// run that started well and then failed (divergence, inverted element): its message names
// the step and the cause. main() prints either; a run that fails after writing some steps
// keeps them in "<folder>.failed" (kept_in says where; docs/output.md).
#pragma once

#include <stdexcept>
#include <string>

namespace hs {

struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct SolveError : std::runtime_error {
  using std::runtime_error::runtime_error;
  std::string kept_in;  // the folder holding the steps that converged, "" if none was kept
  int kept_steps = 0;   // how many output steps it holds
};

}  // namespace hs
