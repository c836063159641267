// The tiled kernel's host side (device_tiled.cuh).
#include <algorithm>
#include <string>
#include <vector>

#include "device_tiled.cuh"

namespace fluidweight::detail {
namespace {

// The tile kernel starts overlapped with the setup kernel up to this many triangles a tile on
// average (overlap_level()).
constexpr long long kOverlapTrianglesPerTile = 64;

}  // namespace

template <typename Real>
TiledKernel<Real>::TiledKernel(const Options& options, int sms, int max_shared)
    : grid_(options.grid),
      sms_(sms),
      max_shared_(max_shared),
      tile_bits_(options.tile == 8    ? 3
                 : options.tile == 16 ? 4
                                      : (options.grid >= 128 ? 4 : 3)) {
  check(cudaStreamCreateWithFlags(&side_, cudaStreamNonBlocking), "cudaStreamCreate");
  check(cudaEventCreateWithFlags(&fork_, cudaEventDisableTiming), "cudaEventCreate");
  check(cudaEventCreateWithFlags(&join_, cudaEventDisableTiming), "cudaEventCreate");
}

template <typename Real>
TiledKernel<Real>::~TiledKernel() {
  cudaEventDestroy(fork_);
  cudaEventDestroy(join_);
  cudaStreamDestroy(side_);
}

template <typename Real>
void TiledKernel<Real>::set_cavities(bool active, int num_cavities, int num_triangles,
                                     int column_capacity) {
  active_ = active;
  num_cavities_ = num_cavities;
  num_triangles_ = num_triangles;
  if (!active) return;
  tiles_per_side_ = (grid_ + (1 << tile_bits_) - 1) >> tile_bits_;
  tile_count_.reserve(static_cast<size_t>(num_cavities_) * tiles_per_side_ * tiles_per_side_ *
                      gpu::kCountStride);
  reserve(column_capacity);
}

template <typename Real>
bool TiledKernel<Real>::grow_lists(int max_tile_count) {
  if (max_tile_count <= tile_capacity_) return false;
  tile_capacity_ = next_power_of_two(max_tile_count);
  return true;
}

template <typename Real>
void TiledKernel<Real>::reserve(int column_capacity) {
  column_capacity_ = column_capacity;
  const size_t tiles = static_cast<size_t>(num_cavities_) * tiles_per_side_ * tiles_per_side_;
  tile_list_.reserve(tiles * tile_capacity_);
  // Both orders start as the grid's (the first call has no counts before it); entry `tiles`
  // is where the tiles empty at the previous call begin: none yet.
  std::vector<int> identity(tiles + 1);
  for (size_t t = 0; t <= tiles; ++t) identity[t] = static_cast<int>(t);
  orders_[0].upload(identity);
  orders_[1].upload(identity);
  const size_t shared = gpu::tile_shared_bytes<Real>(tile_bits_, column_capacity_);
  if (shared > static_cast<size_t>(max_shared_) - 16 * 1024) {
    throw DeviceError("cuda: a column crosses the surface more than " +
                      std::to_string(column_capacity_ / 2) +
                      " times: too many hits for the tiled kernel's shared memory");
  }
  gpu::allow_tile_shared<Real>(shared);
  check(cudaGetLastError(), "cudaFuncSetAttribute");
}

// The tiled kernel takes its tiles heaviest first when they need more than one and a half
// waves of blocks: otherwise the last blocks started decide the kernel's end. The order is
// the previous call's counts sorted by order_kernel beside this call's tile kernel (one
// block sorting on the call's own path cost more than the order gains); a control loop's
// surfaces move little from call to call, and any order of the tiles gives the same result.
template <typename Real>
bool TiledKernel<Real>::ordered() const {
  if (!active_) return false;
  if (tiles() > gpu::max_ordered_tiles()) return false;
  const size_t shared = gpu::tile_shared_bytes<Real>(tile_bits_, column_capacity_);
  const int per_sm = std::max(1, gpu::tile_resident_blocks<Real>(tile_bits_, half_round(), shared));
  // From one and a half waves on: below, the tiles gain more from starting overlapped with
  // the setup kernel (overlap_level(), not with the order) than from the order.
  return 2 * tiles() > 3 * per_sm * sms_;
}

// The tiled kernel stages half as many triangles a round (TILE^2 / 2) when that lets an SM
// hold more of its blocks (many hit slots a column); a tile of more triangles then takes
// more rounds. Tiles of 16 columns only: with tiles of 8 (N < 128) the blocks an SM holds
// are not what limits, and rounds of 32 triangles cost more than they gain.
template <typename Real>
bool TiledKernel<Real>::half_round() const {
  if (tile_bits_ != 4) return false;
  const size_t shared = gpu::tile_shared_bytes<Real>(tile_bits_, column_capacity_);
  return gpu::tile_resident_blocks<Real>(tile_bits_, true, shared) >
         gpu::tile_resident_blocks<Real>(tile_bits_, false, shared);
}

// Which kernels start overlapped with the one before them (launch_overlapped; the measured
// effects are in docs/fluidweight.md): setup_kernel always (its corner loads and launch
// overlap reduce_kernel's end); the tile kernel only without the tile order (with it, its
// waiting blocks fill the GPU before the order kernel's one block starts, which then ends
// after the tiles) and only with few triangles a tile (else the early blocks of a few heavy
// tiles sit beside the setup kernel's); the paper's raster and column kernels not (slower).
template <typename Real>
int TiledKernel<Real>::overlap_level() const {
  const long long tiles = static_cast<long long>(num_cavities_) * tiles_per_side_ * tiles_per_side_;
  const bool light = num_triangles_ <= kOverlapTrianglesPerTile * tiles;
  return active_ && !ordered() && light ? 2 : 1;
}

template <typename Real>
void TiledKernel<Real>::fill(gpu::Batch<Real>& b) const {
  b.tile_bits = tile_bits_;
  b.tiles_per_side = tiles_per_side_;
  b.tile_count = tile_count_.get();
  b.tile_list = tile_list_.get();
  b.tile_capacity = tile_capacity_;
  b.tile_order = ordered() ? orders_[0].get() : nullptr;
  b.overlap = overlap_level();
  b.half_round = active_ && half_round();
  // With the order, the blocks past the previous call's first empty position check several
  // of those tiles each (tile_kernel): over half of a fine grid's tiles can be empty, and a
  // block each held a block slot for its launch and two dependent loads.
  b.group_empty = ordered();
}

template <typename Real>
void TiledKernel<Real>::launch(const gpu::Batch<Real>& b, int graph, cudaStream_t stream) {
  if (!b.tile_order) {
    gpu::launch_setup(b, true, stream);
    gpu::launch_tiles(b, stream);
    return;
  }
  gpu::Batch<Real> bg = b;
  bg.tile_order = orders_[graph].get();
  gpu::launch_setup(bg, true, stream);
  // The order's node is made first, so that its one block starts before the tiles'.
  check(cudaEventRecord(fork_, stream), "cudaEventRecord");
  check(cudaStreamWaitEvent(side_, fork_, 0), "cudaStreamWaitEvent");
  gpu::launch_tile_order(tile_count_.get(), b.big_count, tiles(), orders_[graph ^ 1].get(), side_);
  check(cudaEventRecord(join_, side_), "cudaEventRecord");
  gpu::launch_tiles(bg, stream);
  check(cudaStreamWaitEvent(stream, join_, 0), "cudaStreamWaitEvent");
}

template class TiledKernel<float>;
template class TiledKernel<double>;

}  // namespace fluidweight::detail
