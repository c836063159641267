// partition_tets: METIS k-way partition of the dual graph of the tetrahedra.
#include <metis.h>

#include <limits>
#include <stdexcept>
#include <string>

#include "common/error.hpp"
#include "mesh/distribution.hpp"

namespace hs {

std::vector<int> partition_tets(const Mesh& mesh, int nparts) {
  const int64_t ntets = mesh.num_tets();
  if (nparts < 1) throw std::invalid_argument("partition_tets: nparts must be >= 1");
  if (nparts == 1) return std::vector<int>(ntets, 0);
  if (nparts > ntets)
    throw InputError("the mesh has " + std::to_string(ntets) + " tetrahedra, fewer than the " +
                     std::to_string(nparts) + " parts (MPI ranks) asked for");
  if (4 * ntets > std::numeric_limits<idx_t>::max() ||
      mesh.num_nodes() > std::numeric_limits<idx_t>::max())
    throw InputError("the mesh is too large for METIS's 32-bit indices");

  // Only the 4 vertices: two tetrahedra are dual-graph neighbours when they share a face,
  // i.e. 3 vertices (ncommon = 3). P2 edge nodes would add nothing but cost.
  const int npe = mesh.nodes_per_tet();
  std::vector<idx_t> eptr(ntets + 1), eind(4 * ntets);
  for (int64_t t = 0; t < ntets; ++t) {
    eptr[t] = static_cast<idx_t>(4 * t);
    for (int k = 0; k < 4; ++k) eind[4 * t + k] = static_cast<idx_t>(mesh.tets[t * npe + k]);
  }
  eptr[ntets] = static_cast<idx_t>(4 * ntets);

  idx_t options[METIS_NOPTIONS];
  METIS_SetDefaultOptions(options);
  options[METIS_OPTION_NUMBERING] = 0;
  options[METIS_OPTION_SEED] = 1;      // fixed seed: the same mesh always splits the same way
  options[METIS_OPTION_UFACTOR] = 30;  // parts within 3% of the mean (METIS's k-way default)

  idx_t ne = static_cast<idx_t>(ntets), nn = static_cast<idx_t>(mesh.num_nodes());
  idx_t ncommon = 3, np = nparts, objval = 0;
  std::vector<idx_t> epart(ntets), npart(nn);
  const int status =
      METIS_PartMeshDual(&ne, &nn, eptr.data(), eind.data(), nullptr, nullptr, &ncommon, &np,
                         nullptr, options, &objval, epart.data(), npart.data());
  if (status != METIS_OK)
    throw std::runtime_error("METIS_PartMeshDual failed (status " + std::to_string(status) +
                             ") splitting " + std::to_string(ntets) + " tetrahedra into " +
                             std::to_string(nparts) + " parts");
  return std::vector<int>(epart.begin(), epart.end());
}

}  // namespace hs
