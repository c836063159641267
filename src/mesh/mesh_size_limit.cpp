// The limit on the tetrahedra of a mesh (mesh.max_elements): a lower bound from the model's
// size before gmsh meshes, the count after. gmsh has no option that stops meshing at a count.
#include "mesh/mesh_size_limit.hpp"

#include <gmsh.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <sstream>
#include <vector>

#include "common/error.hpp"

namespace hs {
namespace {

// mesh.max_elements counts tetrahedra after cfg.refine uniform refinements (8 each).
int64_t tets_after_refine(const MeshConfig& cfg, double tets) {
  const double after = tets * std::pow(8.0, cfg.refine);
  return after >= 9e18 ? INT64_MAX : static_cast<int64_t>(after);
}

[[noreturn]] void refuse_size(const MeshConfig& cfg, const std::string& what) {
  throw InputError(cfg.file + ": mesh.max_elements: " + what + ", above the limit of " +
                   std::to_string(cfg.max_elements) +
                   " tetrahedra (check mesh.parameters, or raise mesh.max_elements)");
}

std::string count_text(double n) {
  std::ostringstream s;
  s.precision(3);
  s << n;
  return s.str();
}

// Elements of dimension `dim` of gmsh's current model, of any type.
int64_t element_count(int dim) {
  std::vector<int> types;
  gmsh::model::mesh::getElementTypes(types, dim);
  int64_t count = 0;
  for (int type : types) {
    std::vector<size_t> tags, nodes;
    gmsh::model::mesh::getElementsByType(type, tags, nodes);
    count += static_cast<int64_t>(tags.size());
  }
  return count;
}

// The total length of the model's curves, from below: polylines through points on each.
double curve_length() {
  gmsh::vectorpair curves;
  gmsh::model::getEntities(curves, 1);
  double length = 0;
  for (const auto& [dim, tag] : curves) {
    std::vector<double> lo, hi, coords;
    gmsh::model::getParametrizationBounds(dim, tag, lo, hi);
    if (lo.empty() || hi.empty()) continue;
    std::vector<double> u(33);
    for (size_t k = 0; k < u.size(); ++k) u[k] = lo[0] + (hi[0] - lo[0]) * k / (u.size() - 1);
    gmsh::model::getValue(dim, tag, u, coords);
    for (size_t k = 3; k + 2 < coords.size(); k += 3)
      length += std::hypot(coords[k] - coords[k - 3], coords[k + 1] - coords[k - 2],
                           coords[k + 2] - coords[k - 1]);
  }
  return length;
}

// The total area (dim 2) or volume (dim 3) of an OpenCASCADE model; 0 for gmsh's own kernel,
// which cannot say.
double occ_measure(int dim) {
  gmsh::vectorpair entities;
  gmsh::model::getEntities(entities, dim);
  double total = 0;
  for (const auto& [d, tag] : entities) {
    try {
      double mass = 0;
      gmsh::model::occ::getMass(d, tag, mass);
      total += std::abs(mass);
    } catch (...) {  // not an OpenCASCADE entity
      return 0;
    }
  }
  return total;
}

}  // namespace

// Before meshing: a lower bound on the tetrahedra of the model, from the largest element size
// h its options allow (Mesh.MeshSizeMax, or MeshSizeMin if larger, times MeshSizeFactor when
// above 1). gmsh accepts edges up to about 1.4 h, so counting with edges e = 1.5 h: the curves
// need length / e segments (each an edge of a tetrahedron, which has 6), the surfaces
// area / (sqrt 3 e^2 / 4) triangles (each a face of a tetrahedron, which has 4), the volumes
// volume / (e^3 / (6 sqrt 2)) tetrahedra. On every .geo of meshes/ this bound lies 2 to 5
// times below the tetrahedra gmsh makes. Huge mesh.parameters (a length of 1e9 at a size of
// 0.025) are refused here, before gmsh meshes (and exhausts the memory or fails).
void check_size_estimate(const MeshConfig& cfg) {
  double size_max = 0, size_min = 0, factor = 1;
  gmsh::option::getNumber("Mesh.MeshSizeMax", size_max);
  gmsh::option::getNumber("Mesh.MeshSizeMin", size_min);
  gmsh::option::getNumber("Mesh.MeshSizeFactor", factor);
  const double h = std::max(size_max, size_min) * std::max(factor, 1.0), e = 1.5 * h;
  if (!(e > 0) || !std::isfinite(e)) return;
  const double length = curve_length(), area = occ_measure(2), volume = occ_measure(3);
  const double by_curves = length / e / 6;
  const double by_surfaces = area / (std::sqrt(3.0) / 4 * e * e) / 4;
  const double by_volume = volume / (e * e * e / (6 * std::sqrt(2.0)));
  const double bound = std::max({by_curves, by_surfaces, by_volume});
  if (tets_after_refine(cfg, bound) > cfg.max_elements)
    refuse_size(
        cfg, "meshing would make at least " + count_text(bound) + " tetrahedra (curves " +
                 count_text(length) + " m long, surfaces " + count_text(area) + " m^2, volume " +
                 count_text(volume) + " m^3, at a mesh size of at most " + count_text(h) + " m)" +
                 (cfg.refine > 0 ? " before " + std::to_string(cfg.refine) + " refinements" : ""));
}

void check_tet_count(const MeshConfig& cfg, double tets, const std::string& what) {
  const int64_t after = tets_after_refine(cfg, tets);
  if (after > cfg.max_elements)
    refuse_size(cfg, what + (cfg.refine > 0 ? ", " + std::to_string(after) + " after " +
                                                  std::to_string(cfg.refine) + " refinements"
                                            : ""));
}

void check_meshed_tet_count(const MeshConfig& cfg) {
  const int64_t tets = element_count(3);
  check_tet_count(cfg, static_cast<double>(tets),
                  "the mesh has " + std::to_string(tets) + " tetrahedra");
}

}  // namespace hs
