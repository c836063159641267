// Data shared by the CUDA kernels (docs/fluidweight.md, "CUDA kernels").
//
// One call runs as a captured CUDA graph of three or four kernels over all cavities at once:
//   1. reduce_kernel: Step 1's projected boxes (and for the hydrostatic load the signed
//      volumes) as block partials; it also clears the accumulators.
//   2. setup kernels: each block first reduces the partials of its cavities into their grids
//      (every block alike, so no block waits for another); then Step 2 per triangle (snapped
//      corners, floor or ceiling under the assumed orientation, candidate box; the signed
//      volume summed for the host's check), and for the tiled kernel the binning of triangles
//      to tiles of columns. It starts overlapped with reduce_kernel (launch_overlapped).
// Many blocks adding to one address serialise (docs/fluidweight.md gives the cost), so
// sums over blocks go to partials or to kStripes addresses, never to one.
//   3. Steps 3-5: the leveraging or triangle-parallel raster kernel writing hits per column to
//      global memory, then column_kernel pairing them; or tile_kernel doing both per tile in
//      shared memory.
#pragma once

#include <cuda_runtime.h>

#include <cstdint>
#include <utility>

#include "../geometry.hpp"

namespace fluidweight::detail::gpu {

constexpr unsigned kFullMask = 0xffffffffu;

// Triangle after Steps 1-2 (written by the setup kernels). Empty box (i0 = j0 = 1, i1 = j1 = 0)
// when it covers no column. The box in 16 bits (columns < kMaxGrid = 2^16): 64 bytes in f32
// (the setup kernel writes and the tiles read 86k of them at every call on the armadillo),
// 80 in f64; moved with 16-byte loads and stores (load_tri, store_tri).
template <typename Real>
struct alignas(16) DevTri {
  int x[3], y[3];                 // snapped corners, counter-clockwise
  int flags;                      // bits 0-2: edge k needs E_k >= 1 (not top-left); bit 3: floor;
                                  // bits 4-31: cavity
  unsigned short i0, i1, j0, j1;  // columns whose centres lie in the box
  int vertex[3];                  // global vertex indices of those corners
  Real z[3];                      // heights of the corners above the cavity's lowest vertex
};
static_assert(sizeof(DevTri<float>) == 64 && sizeof(DevTri<double>) == 80, "DevTri layout");

template <typename Real>
__device__ inline DevTri<Real> load_tri(const DevTri<Real>* p) {
  constexpr int kPieces = sizeof(DevTri<Real>) / 16;
  union {
    int4 v[kPieces];
    DevTri<Real> t;
  } u;
  const int4* src = reinterpret_cast<const int4*>(p);
#pragma unroll
  for (int k = 0; k < kPieces; ++k) u.v[k] = __ldg(src + k);
  return u.t;
}

template <typename Real>
__device__ inline void store_tri(DevTri<Real>* p, const DevTri<Real>& t) {
  constexpr int kPieces = sizeof(DevTri<Real>) / 16;
  union {
    int4 v[kPieces];
    DevTri<Real> t;
  } u;
  u.t = t;
  int4* dst = reinterpret_cast<int4*>(p);
#pragma unroll
  for (int k = 0; k < kPieces; ++k) dst[k] = u.v[k];
}

__device__ inline int cavity_of(int flags) { return flags >> 4; }

// Each tile's list count in its own 32-byte sector: the setup kernel's warps bin neighbouring
// tiles at the same moment, and counts packed eight to a sector queued their returning atomics
// behind each other at the L2.
constexpr int kCountStride = 8;
__device__ __forceinline__ size_t count_slot(int tile) {
  return static_cast<size_t>(tile) * kCountStride;
}

constexpr int kStripes = 32;  // accumulators a block adds to: blockIdx.x % kStripes

struct CavityState {
  GridParams grid;
  double signed_volume;
  double sum_heights[kStripes];            // column volume = cell area * their sum
  unsigned long long unmatched[kStripes];  // columns whose floors and ceilings do not pair
  double volume6[kStripes];                // fused kernel: 6 x signed volume, by stripes
};

// Overflows of the fixed-capacity buffers: the host grows them and runs again.
struct Status {
  int max_tile_count;   // largest tile list (tiled)
  int max_column_hits;  // largest number of hits in one column
  int pad[2];
};

// One block of reduce_kernel: a range of a cavity's vertices (kind 0) or triangles (kind 1).
struct ReduceJob {
  int cavity, kind, begin, end;
};

// Everything a kernel reads or writes; passed by value.
template <typename Real>
struct Batch {
  // Inputs.
  const double* xyz;                 // 3 per vertex, all cavities one after the other
  const int* triangles;              // 3 per triangle, global vertex indices
  const int* tri_cavity;             // cavity of each triangle
  const int* cavity_vertex_begin;    // first vertex of each cavity
  const int* cavity_triangle_begin;  // first triangle of each cavity, and the total
  int num_cavities, num_vertices, num_triangles;
  Frame frame;
  int n;         // columns per side
  double rho_g;  // rho |g|
  int head;      // column_head: each floor and ceiling carries the head above it (resolve.cuh)
  // Reduction.
  const ReduceJob* jobs;
  const int* cavity_job_begin;  // jobs of cavity c: [begin[c], begin[c + 1])
  int num_jobs;
  double* partials;  // 8 per job
  // Per call.
  CavityState* cavities;
  Status* status;
  DevTri<Real>* tris;
  Real* out;  // weights (column method, 1 per vertex) or forces (3 per vertex)
  // Paper kernels: hits per column, slot-major (slot * columns + column).
  int* column_count;  // reset to 0 by column_kernel after use
  Real* column_z;
  int* column_tag;  // triangle index, bitwise-negated for floors
  int column_capacity;
  unsigned long long* candidates;  // candidate columns of each setup block (leveraging's c)
  int setup_blocks;
  double alpha;
  // Tiled kernel.
  int tile_bits;  // tile edge = 1 << tile_bits columns
  int tiles_per_side;
  int* tile_count;  // tile t's count at count_slot(t)
  int* tile_list;   // tile * tile_capacity + k
  int tile_capacity;
  int* big_list;  // triangles over many tiles, read by every tile
  int* big_count;
  const int* tile_order;  // positions of the tiles for the blocks (heaviest first), or null
  // Step 2's orientation assumed per cavity (+1 or -1; the host checks it against the signed
  // volume that setup_kernel sums into CavityState::volume6 and runs the call again when it
  // was wrong), or null: from the signed volume of reduce_kernel's partials.
  const int* orientation;
  int overlap;     // host: kernels launched overlapped (launch_overlapped): 0 none, 1 setup_kernel,
                   // 2 also the tile, raster and column kernels
  int half_round;  // tiled kernel: stage TILE^2 / 2 triangles a round, not TILE^2
  int group_empty;  // tiled kernel with tile_order: blocks check the previous call's empty
                    // tiles several at a time
};

// Snapped centre coordinates and edge functions of a DevTri at column (i, j).
template <typename Real>
__device__ inline bool covers_column(const DevTri<Real>& t, int px, int py, int64_t e[3]) {
  e[0] = edge_function(t.x[1], t.y[1], t.x[2], t.y[2], px, py);
  e[1] = edge_function(t.x[2], t.y[2], t.x[0], t.y[0], px, py);
  e[2] = edge_function(t.x[0], t.y[0], t.x[1], t.y[1], px, py);
  return e[0] >= ((t.flags >> 0) & 1) && e[1] >= ((t.flags >> 1) & 1) &&
         e[2] >= ((t.flags >> 2) & 1);
}

template <typename Real>
__device__ inline Real height_at(const DevTri<Real>& t, const int64_t e[3]) {
  Real inv = Real(1) / static_cast<Real>(e[0] + e[1] + e[2]);
  return (static_cast<Real>(e[0]) * t.z[0] + static_cast<Real>(e[1]) * t.z[1] +
          static_cast<Real>(e[2]) * t.z[2]) *
         inv;
}

__device__ inline bool is_floor(int flags) { return (flags >> 3) & 1; }

// 6 x the signed volume of the tetrahedron (o, a, b, c): reduce_kernel, setup_kernel and
// fused_kernel sum it alike.
__device__ __forceinline__ double signed_volume6(const Vec3& a, const Vec3& b, const Vec3& c,
                                                 const Vec3& o) {
  const double ax = a.x - o.x, ay = a.y - o.y, az = a.z - o.z;
  const double bx = b.x - o.x, by = b.y - o.y, bz = b.z - o.z;
  const double cx = c.x - o.x, cy = c.y - o.y, cz = c.z - o.z;
  return ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx);
}

// What the fused kernel reads beside the Batch (kernels_fused.cu). Its accumulators (Batch's
// out, cavities, status) alternate between two sets from call to call: each call clears the
// set of the next one, so that no other kernel or memset is needed.
template <typename Real>
struct FusedArgs {
  const unsigned long long* corners;  // per triangle: its corners' indices in the cavity, 21
                                      // bits each
  const int* vertex_begin;            // first vertex of each cavity, and the total
  // The same ranges for the first kInlineCavities cavities (and those of their triangles),
  // in the kernel's parameters: no load before the first loads.
  static constexpr int kInlineCavities = 16;
  int inline_vertex_begin[kInlineCavities + 1], inline_triangle_begin[kInlineCavities + 1];
  const int* orientation;    // per cavity, +1 or -1: the sign assumed for Step 2
  int tiles_per_side;        // tiles along a side of a cavity's grid
  int cluster_x, cluster_y;  // tiles of a thread-block cluster (the grid is padded to
                             // whole clusters)
  int slice_vertices;        // vertices each block of a cluster snaps
  int item_capacity;         // triangles a tile keeps
  Real* next_out;            // the next call's accumulators, cleared by this one
  int next_out_count;
  CavityState* next_cavities;
  Status* next_status;
};

// Programmatic dependent launch (Hopper): a kernel launched by launch_overlapped may start
// while the kernel before it in the stream still runs, once every block of that one has
// called let_next_start() (or ended); it must call wait_previous() before it reads or writes
// anything the previous kernel reads or writes, and may only load inputs set before the call
// ahead of it. wait_previous() waits for the previous kernel's end and its memory; both are
// no-ops in a kernel launched the ordinary way. This saves a launch gap and the ramp between
// two kernels, and the next kernel's first loads overlap the previous kernel's end.
__device__ __forceinline__ void wait_previous() {
  asm volatile("griddepcontrol.wait;" ::: "memory");
}
__device__ __forceinline__ void let_next_start() {
  asm volatile("griddepcontrol.launch_dependents;" ::: "memory");
}

template <typename... Params, typename... Args>
void launch_overlapped(bool overlap, void (*kernel)(Params...), dim3 grid, dim3 block,
                       size_t shared, cudaStream_t stream, Args&&... args) {
  cudaLaunchAttribute attribute[1];
  attribute[0].id = cudaLaunchAttributeProgrammaticStreamSerialization;
  attribute[0].val.programmaticStreamSerializationAllowed = overlap ? 1 : 0;
  cudaLaunchConfig_t config{};
  config.gridDim = grid;
  config.blockDim = block;
  config.dynamicSmemBytes = shared;
  config.stream = stream;
  config.attrs = attribute;
  config.numAttrs = 1;
  cudaLaunchKernelEx(&config, kernel, std::forward<Args>(args)...);  // errors: end_capture
}

// Host launchers (one translation unit each).
constexpr int kSetupBlock = 256;  // threads a block of the setup and hydrostatic kernels

template <typename Real>
void launch_reduce(const Batch<Real>& b, int zero_out_count, int zero_tile_count,
                   cudaStream_t stream);
template <typename Real>
void launch_setup(const Batch<Real>& b, bool bin_to_tiles, cudaStream_t stream);
template <typename Real>
void launch_raster(const Batch<Real>& b, bool leveraging, int num_sms, cudaStream_t stream);
// Step 5 of the paper kernels; max_shared: the device's shared memory a block may opt into.
template <typename Real>
void launch_columns(const Batch<Real>& b, int max_shared, cudaStream_t stream);
// Shared memory of column_kernel with blocks of `block` columns.
template <typename Real>
size_t column_shared_bytes(int column_capacity, int block);
template <typename Real>
void launch_tiles(const Batch<Real>& b, cudaStream_t stream);
template <typename Real>
void launch_hydrostatic(const Batch<Real>& b, cudaStream_t stream);
// The fused kernel: one launch for Steps 1-5, a block per tile of 1 << tile_bits columns
// (tile_bits 3 or 4), in clusters of f.cluster_x x f.cluster_y blocks.
template <typename Real>
void launch_fused(const Batch<Real>& b, const FusedArgs<Real>& f, int tile_bits,
                  cudaStream_t stream);
template <typename Real>
size_t fused_shared_bytes(int tile_bits, int slice_vertices, int column_capacity,
                          int item_capacity);
// Raises the fused kernel's shared memory limit and allows clusters over 8 blocks; then the
// number of clusters of that shape the device holds at once (0: it cannot run one).
template <typename Real>
int fused_clusters(int tile_bits, int cluster_x, int cluster_y, size_t bytes);
// Dynamic shared memory of tile_kernel; the host raises the kernel's limit to it.
template <typename Real>
size_t tile_shared_bytes(int tile_bits, int column_capacity);
template <typename Real>
void allow_tile_shared(size_t bytes);
// Blocks of tile_kernel an SM holds with that much dynamic shared memory (half_round: the
// kernel that stages half as many triangles at a time, Batch::half_round).
template <typename Real>
int tile_resident_blocks(int tile_bits, bool half_round, size_t shared);
// The tile order (kernels_tiled.cu, order_kernel): all tiles by decreasing count, empty ones
// last; for at most max_ordered_tiles() tiles.
int max_ordered_tiles();
void launch_tile_order(const int* count, const int* big_count, int tiles, int* order,
                       cudaStream_t stream);

}  // namespace fluidweight::detail::gpu
