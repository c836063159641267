// The CUDA backend's side of the tiled kernel (device.cu): its tile, the tiles' lists, and the
// order in which its blocks take the tiles.
#pragma once

#include "device_buffers.cuh"
#include "device_common.cuh"

namespace fluidweight::detail {

template <typename Real>
class TiledKernel {
 public:
  // sms, max_shared: the device's SMs and the shared memory a block may opt into.
  TiledKernel(const Options& options, int sms, int max_shared);
  ~TiledKernel();
  TiledKernel(const TiledKernel&) = delete;
  TiledKernel& operator=(const TiledKernel&) = delete;

  // A new batch; `active` when its calls run the tiled kernel, whose buffers are then sized for
  // `column_capacity` hits a column.
  void set_cavities(bool active, int num_cavities, int num_triangles, int column_capacity);
  // Raises the triangles a tile's list holds to at least max_tile_count; true when it grew.
  bool grow_lists(int max_tile_count);
  // Sizes the tile lists, and the kernel's shared memory for `column_capacity` hits a column
  // (DeviceError when the device has too little).
  void reserve(int column_capacity);

  // The tiles of all cavities.
  int tiles() const { return num_cavities_ * tiles_per_side_ * tiles_per_side_; }
  // Alternate calls take the two tile orders: one read by the call's tiles, the other written
  // for the next.
  bool ordered() const;
  // The batch's tiled-kernel fields, and which kernels start overlapped (every kernel's).
  void fill(gpu::Batch<Real>& b) const;
  // The kernels after reduce_kernel: the setup kernel binning to tiles, then the tiles; with the
  // order, graph g's tiles read order g and the order kernel beside them writes the other.
  void launch(const gpu::Batch<Real>& b, int graph, cudaStream_t stream);

 private:
  bool half_round() const;
  int overlap_level() const;

  int grid_, sms_, max_shared_;
  int tile_bits_;  // Options::tile, else 16 columns from N = 128 on, else 8
  bool active_ = false;
  int num_cavities_ = 0, num_triangles_ = 0, tiles_per_side_ = 0;
  int tile_capacity_ = 1024, column_capacity_ = 0;  // column_capacity_: as last reserved
  DeviceArray<int> tile_count_, tile_list_, orders_[2];
  cudaStream_t side_ = nullptr;  // the order kernel's branch of the graph
  cudaEvent_t fork_ = nullptr, join_ = nullptr;
};

}  // namespace fluidweight::detail
