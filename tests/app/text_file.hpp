// The whole of a file as a string ("" when it cannot be read): the app tests' outputs.
#pragma once

#include <fstream>
#include <sstream>
#include <string>

namespace hs::testing {

inline std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace hs::testing
