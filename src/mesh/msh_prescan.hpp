// A cheap look at a .msh before gmsh reads it. gmsh allocates for the counts that a file's
// $Nodes and $Elements headers claim before it reads a single node: a 6 KB file claiming
// 2^28 nodes took 6.4 GB. Here each count is checked against the bytes that are left in the
// file to hold it, and an ASCII file of format 2 or 4.1 is checked line by line, since gmsh
// crashes on some malformed lines (msh_ascii_check.hpp; docs/reliability.md, "Untrusted
// meshes and surfaces"). No gmsh needed.
#pragma once

#include <cstdint>
#include <string>

namespace hs {

struct MshCounts {
  int64_t nodes = 0;     // as the $Nodes header says
  int64_t elements = 0;  // as the $Elements header says (every dimension)
  int64_t tets = -1;     // Tet4 and Tet10 (format 4.1, and ASCII 2; -1: not counted)
};

// Throws InputError "FILE: SECTION: reason (line N)" when a $Nodes or $Elements header (or,
// in format 4.1, an entity block's header) claims more nodes or elements than the rest of
// the file can hold, a negative count, or blocks whose counts do not add up to the header's;
// in an ASCII file of format 2 or 4.1, also at the first line that does not fit its section
// (check_ascii_msh). Binary files and formats 1, 3 and 4.0 get the count checks only; a
// binary file without these sections passes (gmsh then says what is wrong with it).
MshCounts prescan_msh(const std::string& file);

}  // namespace hs
