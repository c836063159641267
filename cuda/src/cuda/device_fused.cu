// The fused kernel's host side (device_fused.cuh).
#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "device_fused.cuh"

namespace fluidweight::detail {

template <typename Real>
FusedKernel<Real>::FusedKernel(const Options& options, int max_shared)
    : grid_(options.grid),
      max_shared_(max_shared),
      preferred_bits_(options.tile == 8    ? 3
                      : options.tile == 16 ? 4
                                           : 0) {}

template <typename Real>
void FusedKernel<Real>::set_cavities(const std::vector<CavityView>& cavities,
                                     const std::vector<int>& vertex_begin,
                                     const std::vector<int>& triangle_begin,
                                     Accumulators<Real> (&sets)[2]) {
  vertex_begin_ = vertex_begin;
  triangle_begin_ = triangle_begin;
  std::vector<unsigned long long> corners;
  std::vector<int> begin(1, 0);
  max_vertices_ = 0;
  for (const CavityView& v : cavities) {
    for (int t = 0; t < v.num_triangles; ++t) {
      const int* c = v.triangles + 3 * t;
      corners.push_back(static_cast<unsigned long long>(c[0]) |
                        (static_cast<unsigned long long>(c[1]) << 21) |
                        (static_cast<unsigned long long>(c[2]) << 42));
    }
    begin.push_back(begin.back() + v.num_vertices);
    max_vertices_ = std::max(max_vertices_, v.num_vertices);
  }
  const bool fits = max_vertices_ < (1 << 21) && choose_tile();
  if (!fits) {
    throw DeviceError(
        "cuda: the cavities (their tiles' triangles and hits) do not fit the fused kernel's "
        "shared memory (use tiled)");
  }
  corners_.upload(corners);
  vertex_table_.upload(begin);
  const size_t values = 3 * static_cast<size_t>(vertex_begin.back());
  const int num_cavities = static_cast<int>(cavities.size());
  for (Accumulators<Real>& set : sets) {
    set.out.reserve(values, true);
    set.states.reserve(num_cavities, true);
    set.status.reserve(1, true);
  }
}

// The tile (the preferred one, else 16 columns from N = 128 on, else 8) and the cluster of
// tiles: the most blocks (up to 16) for the least padding of the grid to whole clusters, among
// the shapes whose shared memory the device gives.
template <typename Real>
bool FusedKernel<Real>::choose_tile() {
  for (int bits = preferred_bits_ > 0 ? preferred_bits_ : (grid_ >= 128 ? 4 : 3); bits >= 3;
       --bits) {
    const int tiles = (grid_ + (1 << bits) - 1) >> bits;
    std::vector<std::pair<double, std::pair<int, int>>> shapes;
    for (int cx = 1; cx <= std::min(tiles, 16); ++cx) {
      for (int cy = 1; cy <= std::min(tiles, 16 / cx); ++cy) {
        const double waste = static_cast<double>((tiles + cx - 1) / cx * cx) *
                             ((tiles + cy - 1) / cy * cy) / (static_cast<double>(tiles) * tiles);
        shapes.push_back({-(cx * cy) / (waste * waste), {cx, cy}});
      }
    }
    std::sort(shapes.begin(), shapes.end());
    for (const auto& shape : shapes) {
      const int cx = shape.second.first, cy = shape.second.second;
      const int slice = (max_vertices_ + cx * cy - 1) / (cx * cy);
      const size_t bytes =
          gpu::fused_shared_bytes<Real>(bits, std::max(slice, 1), column_capacity_, item_capacity_);
      if (bytes > static_cast<size_t>(max_shared_)) continue;
      const int resident = gpu::fused_clusters<Real>(bits, cx, cy, bytes);
      if (resident > 0) {
        tile_bits_ = bits;
        cluster_x_ = cx;
        cluster_y_ = cy;
        slice_vertices_ = std::max(slice, 1);
        return true;
      }
    }
  }
  return false;
}

template <typename Real>
bool FusedKernel<Real>::grow(const gpu::Status& s) {
  bool again = false;
  if (s.max_tile_count > item_capacity_) {
    item_capacity_ = next_power_of_two(s.max_tile_count);
    again = true;
  }
  if (s.max_column_hits > column_capacity_) {
    column_capacity_ = (s.max_column_hits + 3) / 4 * 4;
    again = true;
  }
  if (again && !choose_tile()) {
    throw DeviceError("cuda: a tile's triangles (" + std::to_string(s.max_tile_count) +
                      ") or a column's hits (" + std::to_string(s.max_column_hits) +
                      ") do not fit the fused kernel's shared memory (use tiled)");
  }
  return again;
}

template <typename Real>
void FusedKernel<Real>::launch(gpu::Batch<Real> b, const Accumulators<Real>& call,
                               const Accumulators<Real>& next, cudaStream_t stream) const {
  b.out = call.out.get();
  b.cavities = call.states.get();
  b.status = call.status.get();
  b.column_capacity = column_capacity_;
  gpu::FusedArgs<Real> f{};
  f.corners = corners_.get();
  f.vertex_begin = vertex_table_.get();
  const int num_cavities = static_cast<int>(vertex_begin_.size()) - 1;
  for (int c = 0; c <= std::min(num_cavities, gpu::FusedArgs<Real>::kInlineCavities); ++c) {
    f.inline_vertex_begin[c] = vertex_begin_[c];
    f.inline_triangle_begin[c] = triangle_begin_[c];
  }
  f.orientation = b.orientation;  // the column method's, always set
  f.tiles_per_side = (grid_ + (1 << tile_bits_) - 1) >> tile_bits_;
  f.cluster_x = cluster_x_;
  f.cluster_y = cluster_y_;
  f.slice_vertices = slice_vertices_;
  f.item_capacity = item_capacity_;
  f.next_out = next.out.get();
  f.next_out_count = b.num_vertices;
  f.next_cavities = next.states.get();
  f.next_status = next.status.get();
  gpu::launch_fused(b, f, tile_bits_, stream);
}

template class FusedKernel<float>;
template class FusedKernel<double>;

}  // namespace fluidweight::detail
