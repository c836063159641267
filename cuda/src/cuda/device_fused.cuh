// The CUDA backend's side of the fused kernel (device.cu): its inputs, the tile and cluster it
// runs with, and the capacities that grow when a call overflows them.
#pragma once

#include <vector>

#include "../cpu.hpp"
#include "device_buffers.cuh"
#include "device_common.cuh"

namespace fluidweight::detail {

// A call's accumulators: forces or weights, the cavities' sums, the overflow status. The fused
// kernel alternates between two sets (FusedArgs); the other kernels use the first alone.
template <typename Real>
struct Accumulators {
  DeviceArray<Real> out;
  DeviceArray<gpu::CavityState> states;
  DeviceArray<gpu::Status> status;
};

template <typename Real>
class FusedKernel {
 public:
  // max_shared: the shared memory a block may opt into on the device.
  FusedKernel(const Options& options, int max_shared);

  // Corners packed per triangle, vertex ranges; both sets of accumulators cleared (each call
  // clears the next one's). Chooses the tile; throws DeviceError when none fits.
  void set_cavities(const std::vector<CavityView>& cavities, const std::vector<int>& vertex_begin,
                    const std::vector<int>& triangle_begin, Accumulators<Real> (&sets)[2]);

  // Grows what overflowed; true when the call must run again (and the graphs be captured
  // again). Throws DeviceError when the grown capacities fit no tile.
  bool grow(const gpu::Status& s);

  // The call on the accumulators `call`, clearing `next`; b as for the other kernels.
  void launch(gpu::Batch<Real> b, const Accumulators<Real>& call, const Accumulators<Real>& next,
              cudaStream_t stream) const;

 private:
  bool choose_tile();

  int grid_, max_shared_;
  int preferred_bits_;  // Options::tile, else 0: chosen by choose_tile()
  int tile_bits_ = 4, cluster_x_ = 1, cluster_y_ = 1, slice_vertices_ = 1;
  // Hits a column keeps, triangles a tile keeps: grown on overflow, kept across batches.
  int column_capacity_ = 4, item_capacity_ = 512;
  int max_vertices_ = 0;
  std::vector<int> vertex_begin_, triangle_begin_;  // for FusedArgs' inline ranges
  DeviceArray<unsigned long long> corners_;
  DeviceArray<int> vertex_table_;  // FusedArgs::vertex_begin
};

}  // namespace fluidweight::detail
