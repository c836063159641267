// A Mesh as bytes, for the way back from the confined gmsh process (gmsh_process.hpp) to the
// run. The bytes come from a process that parsed untrusted input, so decoding trusts nothing:
// every count is checked against the bytes left before anything is allocated, and every index
// against what it indexes.
#pragma once

#include <string>
#include <string_view>

#include "mesh/mesh.hpp"

namespace hs {

std::string encode_mesh(const Mesh& mesh);

// Throws InputError naming `file` when the bytes are not a whole, consistent encoded mesh.
Mesh decode_mesh(std::string_view bytes, const std::string& file);

}  // namespace hs
