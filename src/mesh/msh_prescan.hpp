// A cheap look at a .msh before gmsh reads it. gmsh allocates for the counts that a file's
// $Nodes and $Elements headers claim before it reads a single node: a 6 KB file claiming
// 2^28 nodes took 6.4 GB. Here each count is checked against the bytes that are left in the
// file to hold it (docs/reliability.md, "Untrusted meshes and surfaces"). No gmsh needed.
#pragma once

#include <cstdint>
#include <string>

namespace hs {

struct MshCounts {
  int64_t nodes = 0;     // as the $Nodes header says
  int64_t elements = 0;  // as the $Elements header says (every dimension)
  int64_t tets = -1;     // Tet4 and Tet10 of the blocks (format 4 only; -1: not counted)
};

// Throws InputError "FILE: SECTION: reason (line N)" when a $Nodes or $Elements header (or,
// in format 4, ASCII or binary, an entity block's header) claims more nodes or elements
// than the rest of the file can hold, a negative count, or blocks whose counts do not add up
// to the header's. Formats 1, 2 and 4 are read; a file without these sections passes (gmsh
// then says what is wrong with it).
MshCounts prescan_msh(const std::string& file);

}  // namespace hs
