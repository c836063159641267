// Where the interactive mode (`hydrosoft DECK --targets -`, docs/control.md) reads its target
// lines and writes its JSON lines, on rank 0: standard input, and standard output flushed
// after each line, unless given. main gives a descriptor of its own so that nothing else
// reaches standard output; a test gives strings. write_line returns false when the line could
// not be written (the client closed its end of standard output): the session then ends as at
// the end of its input.
#pragma once

#include <petscvec.h>

#include <functional>
#include <istream>
#include <string>

namespace hs {

struct InteractiveIo {
  std::istream* input = nullptr;                            // null: std::cin
  std::function<bool(const std::string& line)> write_line;  // null: std::cout, flushed
  // Tests: called on every rank after an interactive line's control steps, before its answer
  // is checked (a test makes the step fail there, e.g. with a NaN in u).
  std::function<void(Vec u, int line)> after_steps;
};

}  // namespace hs
