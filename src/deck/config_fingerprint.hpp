// A number that tells whether two runs solve the same problem: a 64-bit FNV-1a hash of the
// resolved configuration (format_config) without what does not change the solution: the
// output section, the deck's path and the mesh file's folder (a checkpoint also checks the
// mesh by its sizes and coordinates). A restart compares its deck's with its checkpoint's.
#pragma once

#include <string>

#include "deck/config.hpp"

namespace hs {

// 16 hexadecimal digits.
std::string config_fingerprint(const Config& config);

}  // namespace hs
