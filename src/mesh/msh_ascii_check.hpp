// The structure of an ASCII .msh of format 2 (2.1, 2.2) or 4.1, checked line by line before
// gmsh reads it. gmsh 4.8 reads these files with fscanf and trusts what it reads: a count
// line doubled in $PhysicalNames made it index its table of four dimensions with 8, and a
// node line one field short in format 2.2 shifted every later number and left a node the
// elements name undefined; both crashed it (SIGSEGV). Here every line of $MeshFormat,
// $PhysicalNames, $Entities, $Nodes and $Elements must hold the fields its format gives it,
// numbers where numbers go, and each section as many lines as its counts say, then its end
// (docs/reliability.md, "Untrusted meshes and surfaces").
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "mesh/msh_prescan.hpp"

namespace hs {

// Throws InputError "FILE: SECTION: reason (line N)" at the first line that does not fit;
// returns the counts of $Nodes and $Elements and the tetrahedra. `text` is the whole file,
// `version` the number of its $MeshFormat line (2 < version < 3, or 4.1 and above). The file
// is read once, without copying it or allocating for its counts.
MshCounts check_ascii_msh(const std::string& file, std::string_view text, double version);

// The reason a count of `count` items of at least `bytes` bytes each cannot be right when
// `left` bytes of the `size`-byte file follow it (negative, or more than fit), or "".
std::string msh_count_problem(int64_t count, int64_t bytes, int64_t left, int64_t size,
                              const std::string& what);

// Nodes of gmsh element type `type`, or -1 for a type hydrosoft does not know.
int msh_element_nodes(int64_t type);

}  // namespace hs
