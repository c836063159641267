// The 3x3 blocks of the tangent one rank assembles: one per pair of its local nodes that share
// a tetrahedron (a CSR pattern over the local nodes), and for each local tetrahedron the block
// of each of its node pairs. Element (and face) matrices are summed into these blocks before
// PETSc sees them, so PETSc's assembly by coordinates gets each entry once, not once per
// tetrahedron around it: for P1 about 6 times fewer entries, and as much less memory and
// set-up time in MatSetPreallocationCOO (docs/architecture.md, "Assembly of the tangent").
// Pure: no PETSc.
#pragma once

#include <cstdint>
#include <vector>

namespace hs {

class NodePairBlocks {
 public:
  // tet_nodes: npe local node indices per tetrahedron; num_local: the number of local nodes.
  NodePairBlocks(const std::vector<int32_t>& tet_nodes, int npe, int64_t num_local);

  int64_t num_pairs() const { return static_cast<int64_t>(columns_.size()); }
  int64_t num_nodes() const { return static_cast<int64_t>(offsets_.size()) - 1; }
  // The pairs of row node a are slots offsets(a) .. offsets(a + 1) - 1, columns ascending.
  int64_t offset(int64_t a) const { return offsets_[a]; }
  int32_t column(int64_t slot) const { return columns_[slot]; }
  // The slot of pair (a, b); -1 if the two nodes share no tetrahedron.
  int64_t slot(int32_t a, int32_t b) const;

  // values (9 per slot, row-major 3x3) += the element matrix K of local tetrahedron e
  // (3 npe x 3 npe, row-major, dof 3 a + d for its node a).
  void add_tet(int64_t e, const double* K, double* values) const;
  // The same for a matrix over any n nodes that share a tetrahedron (a face's).
  void add_nodes(const int32_t* nodes, int n, const double* K, double* values) const;

 private:
  int npe_;
  std::vector<int64_t> offsets_;
  std::vector<int32_t> columns_;
  std::vector<int64_t> tet_slots_;  // npe * npe per tetrahedron
};

}  // namespace hs
