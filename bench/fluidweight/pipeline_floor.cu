// What any binned column pipeline must pay on this GPU before Steps 3-5 do any work.
//
// The column method has two dependencies that no kernel design removes: the grid is the exact
// box of the vertices, so no triangle can be snapped before every vertex has been read (a
// grid-wide reduction), and a column's Step 5 needs every triangle that covers it, so the
// triangles must be exchanged between the threads that read them and the threads that own
// columns (binning, a grid-wide all-to-all) or read by every owner (redundant). This program
// times skeletons of those dependency chains on a real mesh: the same loads, reductions,
// atomics, lists and output atomics as the tiled pipeline, with no raster and no resolution,
// each written in its cheapest form. Graph replays between CUDA events, medians.
//
//   floor       one empty kernel
//   read        one kernel: each triangle's corners loaded, one coalesced store a triangle
//   touch       one kernel: each triangle's corners loaded, one atomic a corner (no box)
//   box+touch   two kernels (programmatic dependent launch): box partials; every block
//               reduces them, then as `touch`
//   box+bin+tiles  three kernels: as `box+touch` but each triangle is counted and listed in
//               the tiles its box meets (padded counts) with a 16-byte record; then one block
//               a tile loads its count, list (at most kListCap entries) and records and adds
//               one value to each listed floor's three vertices; timed also with the tile
//               kernel started overlapped
//   cooperative one cooperative kernel, grid barriers between box, binning and tiles (tiles by
//               stride over the resident blocks)
//   redundant   one kernel, a block a tile: every block reduces the whole box itself and reads
//               every triangle, keeping those over its tile (the fused design without clusters)
//   box + hits + columns  the plain port: three kernels, every third candidate of a triangle's
//               box appended to its column's global slots by an atomic, then a thread a column
//
// Build: part of the cuda/ build (target pipeline_floor). Usage: pipeline_floor MESH GRID
// [CAVITIES [TILE]] (CAVITIES copies of the mesh side by side, each its own grid; tiles of
// TILE x TILE columns, default 16).
#include <cooperative_groups.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cub/block/block_reduce.cuh>
#include <vector>

#include "fluidweight/mesh_io.hpp"

namespace cg = cooperative_groups;

namespace {

constexpr int kBlock = 256;
constexpr int kStride = 8;  // a tile's count in its own 32-byte sector
constexpr int kListCap = 1024;

void check(cudaError_t e, const char* what) {
  if (e != cudaSuccess) {
    std::fprintf(stderr, "%s: %s\n", what, cudaGetErrorString(e));
    std::exit(2);
  }
}

struct Mesh {
  const double* xyz;                  // 3 a vertex
  const int* tri;                     // 3 a triangle
  int vertices, triangles, cavities;  // each cavity has vertices / cavities vertices, alike
  int n;                              // grid N
  int tile;                           // tile side in columns
  int tiles_side;                     // tiles along a side, per cavity
  float4* partials;                   // per reduce block: min e1, max e1, min e2, max e2
  int reduce_blocks;
  int* count;         // per tile, padded
  int* list;          // per tile, kListCap entries
  float4* records;    // per triangle: snapped box as floats, floor flag
  float* out;         // per vertex
  int* column_count;  // per column (global-hits skeleton)
  int* column_hits;   // per column, 4 slots
};

struct Box {
  float v[4];
};
struct BoxOp {
  __device__ Box operator()(const Box& a, const Box& b) const {
    return {{fminf(a.v[0], b.v[0]), fmaxf(a.v[1], b.v[1]), fminf(a.v[2], b.v[2]),
             fmaxf(a.v[3], b.v[3])}};
  }
};
using BoxReduce = cub::BlockReduce<Box, kBlock>;

__device__ Box empty_box() { return {{INFINITY, -INFINITY, INFINITY, -INFINITY}}; }

// Gravity along -y: e1 = z, e2 = x.
__device__ Box vertex_box(const double* xyz, int v) {
  const float e1 = static_cast<float>(xyz[3 * v + 2]), e2 = static_cast<float>(xyz[3 * v]);
  return {{e1, e1, e2, e2}};
}

__device__ void pdl_wait() { asm volatile("griddepcontrol.wait;" ::: "memory"); }
__device__ void pdl_start_next() { asm volatile("griddepcontrol.launch_dependents;" ::: "memory"); }

// Box partials: a cavity's vertices in chunks of 4 kBlock, a block a chunk.
__device__ int chunks_per_cavity(const Mesh& m) {
  return (m.vertices / m.cavities + 4 * kBlock - 1) / (4 * kBlock);
}
__device__ void box_partials(const Mesh& m, int block) {
  __shared__ typename BoxReduce::TempStorage storage;
  const int chunks = chunks_per_cavity(m), per = m.vertices / m.cavities;
  const int cavity = block / chunks, chunk = block % chunks;
  Box b = empty_box();
  for (int k = 0; k < 4; ++k) {
    const int v = (chunk * 4 + k) * kBlock + threadIdx.x;
    if (v < per) b = BoxOp()(b, vertex_box(m.xyz, cavity * per + v));
  }
  b = BoxReduce(storage).Reduce(b, BoxOp());
  if (threadIdx.x == 0) m.partials[block] = make_float4(b.v[0], b.v[1], b.v[2], b.v[3]);
}

// A cavity's box from the partials (every block alike).
__device__ Box cavity_box(const Mesh& m, int cavity) {
  __shared__ typename BoxReduce::TempStorage storage;
  __shared__ Box result;
  const int chunks = chunks_per_cavity(m);
  const int first = cavity * chunks, last = first + chunks - 1;
  Box b = empty_box();
  for (int k = first + threadIdx.x; k <= last; k += blockDim.x) {
    const float4 p = m.partials[k];
    b = BoxOp()(b, {{p.x, p.y, p.z, p.w}});
  }
  b = BoxReduce(storage).Reduce(b, BoxOp());
  __syncthreads();
  if (threadIdx.x == 0) result = b;
  __syncthreads();
  return result;
}

struct Corners {
  float e1[3], e2[3];
  int v[3];
};
__device__ Corners load_corners(const Mesh& m, int t) {
  Corners c;
  for (int k = 0; k < 3; ++k) c.v[k] = m.tri[3 * t + k];
  for (int k = 0; k < 3; ++k) {
    c.e1[k] = static_cast<float>(m.xyz[3 * c.v[k] + 2]);
    c.e2[k] = static_cast<float>(m.xyz[3 * c.v[k]]);
  }
  return c;
}

// Snapped box of a triangle in columns, and whether it is a floor (clockwise seen from above).
struct TriBox {
  int i0, i1, j0, j1;
  bool floor;
};
__device__ TriBox tri_box(const Corners& c, const Box& b, int n) {
  const float si = n / fmaxf(b.v[1] - b.v[0], 1e-30f), sj = n / fmaxf(b.v[3] - b.v[2], 1e-30f);
  float lo_i = 1e30f, hi_i = -1e30f, lo_j = 1e30f, hi_j = -1e30f;
  for (int k = 0; k < 3; ++k) {
    const float i = (c.e1[k] - b.v[0]) * si, j = (c.e2[k] - b.v[2]) * sj;
    lo_i = fminf(lo_i, i), hi_i = fmaxf(hi_i, i), lo_j = fminf(lo_j, j), hi_j = fmaxf(hi_j, j);
  }
  const float cross =
      (c.e1[1] - c.e1[0]) * (c.e2[2] - c.e2[0]) - (c.e1[2] - c.e1[0]) * (c.e2[1] - c.e2[0]);
  TriBox t;
  t.i0 = max(0, __float2int_ru(lo_i - 0.5f));
  t.i1 = min(n - 1, __float2int_rd(hi_i - 0.5f));
  t.j0 = max(0, __float2int_ru(lo_j - 0.5f));
  t.j1 = min(n - 1, __float2int_rd(hi_j - 0.5f));
  t.floor = cross < 0;
  return t;
}

// Counts and lists triangle t in the tiles its box meets; writes its record.
__device__ void bin(const Mesh& m, int t, int cavity, const TriBox& x) {
  m.records[t] = make_float4(x.i0, x.j0, x.i1, x.floor ? 1.f : 0.f);
  if (x.i0 > x.i1 || x.j0 > x.j1) return;
  const int base = cavity * m.tiles_side * m.tiles_side;
  for (int ti = x.i0 / m.tile; ti <= x.i1 / m.tile; ++ti)
    for (int tj = x.j0 / m.tile; tj <= x.j1 / m.tile; ++tj) {
      const int tile = base + ti * m.tiles_side + tj;
      const int slot = atomicAdd(&m.count[tile * kStride], 1);
      if (slot < kListCap) m.list[tile * kListCap + slot] = t;
    }
}

// One tile: its listed floors add a value to their three vertices; the count is cleared for
// the next call (the skeleton's stand-in for Steps 3-5 and the nodal weights).
__device__ void tile_work(const Mesh& m, int tile) {
  __shared__ int count;
  if (threadIdx.x == 0) count = min(m.count[tile * kStride], kListCap);
  __syncthreads();
  for (int k = threadIdx.x; k < count; k += blockDim.x) {
    const int t = m.list[tile * kListCap + k];
    const float4 r = m.records[t];
    if (r.w > 0.5f) {
      const float w = 1e-3f * (r.z - r.x + 1);
      for (int q = 0; q < 3; ++q) atomicAdd(&m.out[m.tri[3 * t + q]], w);
    }
  }
  __syncthreads();
  if (threadIdx.x == 0) m.count[tile * kStride] = 0;
}

__global__ void empty_kernel() {}

__global__ void __launch_bounds__(kBlock) touch_kernel(Mesh m) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= m.triangles) return;
  const Corners c = load_corners(m, t);
  const float w = 1e-3f * (c.e1[0] + c.e2[1]);
  for (int q = 0; q < 3; ++q) atomicAdd(&m.out[c.v[q]], w);
}

// As touch_kernel, one coalesced store a triangle instead of the corners' atomics.
__global__ void __launch_bounds__(kBlock) read_kernel(Mesh m) {
  const int t = blockIdx.x * blockDim.x + threadIdx.x;
  if (t >= m.triangles) return;
  const Corners c = load_corners(m, t);
  m.records[t] = make_float4(c.e1[0], c.e2[1], c.e1[2], c.e2[0]);
}

// The plain port's skeleton: every third candidate of a triangle's box is a hit, appended to
// its column's four global slots by an atomic; then a thread a column adds one value to its
// first hit's vertex and clears the column.
__global__ void __launch_bounds__(kBlock) hits_kernel(Mesh m) {
  const int t = min(static_cast<int>(blockIdx.x * blockDim.x + threadIdx.x), m.triangles - 1);
  const Corners c = load_corners(m, t);
  pdl_wait();
  const Box b = cavity_box(m, 0);
  if (blockIdx.x * blockDim.x + threadIdx.x >= m.triangles) return;
  const TriBox x = tri_box(c, b, m.n);
  for (int i = x.i0; i <= x.i1; ++i)
    for (int j = x.j0; j <= x.j1; ++j)
      if ((i + j) % 3 == 0) {
        const int col = i * m.n + j;
        const int slot = atomicAdd(&m.column_count[col], 1);
        if (slot < 4) m.column_hits[4 * col + slot] = t;
      }
}

__global__ void __launch_bounds__(kBlock) columns_kernel(Mesh m) {
  const int col = blockIdx.x * blockDim.x + threadIdx.x;
  if (col >= m.n * m.n) return;
  const int count = m.column_count[col];
  if (count == 0) return;
  atomicAdd(&m.out[m.tri[3 * m.column_hits[4 * col]]], 1e-3f * count);
  m.column_count[col] = 0;
}

__global__ void __launch_bounds__(kBlock) box_kernel(Mesh m) {
  pdl_start_next();
  box_partials(m, blockIdx.x);
}

template <bool kBin>
__global__ void __launch_bounds__(kBlock) setup_kernel(Mesh m) {
  const int t0 = blockIdx.x * blockDim.x;
  const int t = min(t0 + static_cast<int>(threadIdx.x), m.triangles - 1);
  const int per = m.triangles / m.cavities;
  const Corners c = load_corners(m, t);  // inputs: loaded while box_kernel runs
  pdl_wait();
  const int cavity = t0 / per;  // blocks do not straddle cavities in the cases timed
  const Box b = cavity_box(m, cavity);
  if (t0 + static_cast<int>(threadIdx.x) >= m.triangles) return;
  const TriBox x = tri_box(c, b, m.n);
  if (kBin) {
    bin(m, t, t / per, x);
  } else if (x.floor) {
    for (int q = 0; q < 3; ++q) atomicAdd(&m.out[c.v[q]], 1e-3f * (x.i1 - x.i0 + 1));
  }
}

__global__ void __launch_bounds__(kBlock) tile_kernel(Mesh m) {
  pdl_wait();
  tile_work(m, blockIdx.x);
}

// One cooperative kernel: box, grid barrier, binning, grid barrier, tiles by stride.
__global__ void __launch_bounds__(kBlock) cooperative_kernel(Mesh m) {
  cg::grid_group grid = cg::this_grid();
  const int per = m.triangles / m.cavities;
  for (int k = blockIdx.x; k < m.reduce_blocks; k += gridDim.x) box_partials(m, k);
  grid.sync();
  for (int t0 = blockIdx.x * blockDim.x; t0 < m.triangles; t0 += gridDim.x * blockDim.x) {
    const int t = min(t0 + static_cast<int>(threadIdx.x), m.triangles - 1);
    const Corners c = load_corners(m, t);
    const Box b = cavity_box(m, t0 / per);
    if (t0 + static_cast<int>(threadIdx.x) < m.triangles) bin(m, t, t / per, tri_box(c, b, m.n));
  }
  grid.sync();
  const int tiles = m.cavities * m.tiles_side * m.tiles_side;
  for (int tile = blockIdx.x; tile < tiles; tile += gridDim.x) tile_work(m, tile);
}

// One kernel, a block a tile, nothing shared between blocks: the block reduces its cavity's
// whole box and reads all of its triangles, keeping the floors over its tile.
__global__ void __launch_bounds__(kBlock) redundant_kernel(Mesh m) {
  __shared__ typename BoxReduce::TempStorage storage;
  __shared__ Box box;
  const int tiles = m.tiles_side * m.tiles_side;
  const int cavity = blockIdx.x / tiles, tile = blockIdx.x % tiles;
  const int per_v = m.vertices / m.cavities, per_t = m.triangles / m.cavities;
  Box b = empty_box();
  for (int v = threadIdx.x; v < per_v; v += blockDim.x)
    b = BoxOp()(b, vertex_box(m.xyz, cavity * per_v + v));
  b = BoxReduce(storage).Reduce(b, BoxOp());
  if (threadIdx.x == 0) box = b;
  __syncthreads();
  const int ti = tile / m.tiles_side, tj = tile % m.tiles_side;  // tile side m.tile
  float w = 0;
  int mine = -1;
  for (int k = threadIdx.x; k < per_t; k += blockDim.x) {
    const int t = cavity * per_t + k;
    const TriBox x = tri_box(load_corners(m, t), box, m.n);
    if (x.floor && x.i0 <= ti * m.tile + m.tile - 1 && x.i1 >= ti * m.tile &&
        x.j0 <= tj * m.tile + m.tile - 1 && x.j1 >= tj * m.tile) {
      w += 1e-3f;
      mine = t;
    }
  }
  if (mine >= 0) atomicAdd(&m.out[m.tri[3 * mine]], w);
}

template <typename Launch>
float time_graph(cudaStream_t s, Launch launch) {
  cudaGraph_t g;
  cudaGraphExec_t e;
  check(cudaStreamBeginCapture(s, cudaStreamCaptureModeThreadLocal), "capture");
  launch();
  check(cudaStreamEndCapture(s, &g), "end capture");
  check(cudaGraphInstantiate(&e, g, 0), "instantiate");
  cudaEvent_t a, b;
  cudaEventCreate(&a);
  cudaEventCreate(&b);
  std::vector<float> us;
  for (int r = 0; r < 300; ++r) {
    cudaEventRecord(a, s);
    check(cudaGraphLaunch(e, s), "graph launch");
    cudaEventRecord(b, s);
    check(cudaEventSynchronize(b), "replay");
    float ms;
    cudaEventElapsedTime(&ms, a, b);
    if (r >= 30) us.push_back(1000 * ms);
  }
  check(cudaGetLastError(), "kernels");
  std::sort(us.begin(), us.end());
  cudaGraphExecDestroy(e);
  cudaGraphDestroy(g);
  return us[us.size() / 2];
}

void launch(void (*kernel)(Mesh), int blocks, cudaStream_t s, bool overlap, const Mesh& m) {
  cudaLaunchAttribute attribute[1];
  attribute[0].id = cudaLaunchAttributeProgrammaticStreamSerialization;
  attribute[0].val.programmaticStreamSerializationAllowed = overlap ? 1 : 0;
  cudaLaunchConfig_t config{};
  config.gridDim = blocks;
  config.blockDim = kBlock;
  config.stream = s;
  config.attrs = attribute;
  config.numAttrs = 1;
  check(cudaLaunchKernelEx(&config, kernel, m), "launch");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: pipeline_floor MESH GRID [CAVITIES]\n");
    return 2;
  }
  const fluidweight::SurfaceMesh mesh = fluidweight::read_surface(argv[1]);
  const int n = std::atoi(argv[2]);
  const int cavities = argc > 3 ? std::atoi(argv[3]) : 1;
  const int tile_side = argc > 4 ? std::atoi(argv[4]) : 16;
  const int nv = static_cast<int>(mesh.vertices.size() / 3);
  const int nt = static_cast<int>(mesh.triangles.size() / 3);
  // Copies side by side; triangles per cavity rounded to whole blocks so that no setup block
  // straddles two cavities (the extra triangles repeat the last one).
  const int per_t = (nt + kBlock - 1) / kBlock * kBlock;
  std::vector<double> xyz;
  std::vector<int> tri;
  for (int c = 0; c < cavities; ++c) {
    for (int v = 0; v < nv; ++v) {
      xyz.push_back(mesh.vertices[3 * v] + 3.0 * c);
      xyz.push_back(mesh.vertices[3 * v + 1]);
      xyz.push_back(mesh.vertices[3 * v + 2]);
    }
    for (int t = 0; t < per_t; ++t)
      for (int k = 0; k < 3; ++k)
        tri.push_back(mesh.triangles[3 * std::min(t, nt - 1) + k] + c * nv);
  }
  Mesh m{};
  m.vertices = nv * cavities;
  m.triangles = per_t * cavities;
  m.cavities = cavities;
  m.n = n;
  m.tile = tile_side;
  m.tiles_side = (n + tile_side - 1) / tile_side;
  m.reduce_blocks = cavities * ((nv + 4 * kBlock - 1) / (4 * kBlock));
  const int tiles = cavities * m.tiles_side * m.tiles_side;
  double* d_xyz;
  int* d_tri;
  check(cudaMalloc(&d_xyz, xyz.size() * sizeof(double)), "malloc");
  check(cudaMalloc(&d_tri, tri.size() * sizeof(int)), "malloc");
  cudaMemcpy(d_xyz, xyz.data(), xyz.size() * sizeof(double), cudaMemcpyHostToDevice);
  cudaMemcpy(d_tri, tri.data(), tri.size() * sizeof(int), cudaMemcpyHostToDevice);
  m.xyz = d_xyz;
  m.tri = d_tri;
  check(cudaMalloc(&m.partials, m.reduce_blocks * sizeof(float4)), "malloc");
  check(cudaMalloc(&m.count, tiles * kStride * sizeof(int)), "malloc");
  check(cudaMemset(m.count, 0, tiles * kStride * sizeof(int)), "memset");
  check(cudaMalloc(&m.list, static_cast<size_t>(tiles) * kListCap * sizeof(int)), "malloc");
  check(cudaMalloc(&m.records, m.triangles * sizeof(float4)), "malloc");
  check(cudaMalloc(&m.out, m.vertices * sizeof(float)), "malloc");
  check(cudaMemset(m.out, 0, m.vertices * sizeof(float)), "memset");
  if (cavities == 1) {
    check(cudaMalloc(&m.column_count, static_cast<size_t>(n) * n * sizeof(int)), "malloc");
    check(cudaMemset(m.column_count, 0, static_cast<size_t>(n) * n * sizeof(int)), "memset");
    check(cudaMalloc(&m.column_hits, 4 * static_cast<size_t>(n) * n * sizeof(int)), "malloc");
  }

  cudaStream_t s;
  cudaStreamCreate(&s);
  const int tri_blocks = m.triangles / kBlock;
  int per_sm = 0, sms = 0;
  cudaOccupancyMaxActiveBlocksPerMultiprocessor(&per_sm, cooperative_kernel, kBlock, 0);
  cudaDeviceGetAttribute(&sms, cudaDevAttrMultiProcessorCount, 0);
  const int coop_blocks = per_sm * sms;

  // The binned skeleton's work: (triangle, tile) pairs of one call, counted before the tiles.
  launch(box_kernel, m.reduce_blocks, s, false, m);
  launch(setup_kernel<true>, tri_blocks, s, false, m);
  std::vector<int> counts(static_cast<size_t>(tiles) * kStride);
  check(cudaMemcpy(counts.data(), m.count, counts.size() * sizeof(int), cudaMemcpyDeviceToHost),
        "counts");
  long pairs = 0, busy = 0;
  for (int t = 0; t < tiles; ++t) pairs += counts[t * kStride], busy += counts[t * kStride] > 0;
  launch(tile_kernel, tiles, s, false, m);  // clears the counts
  check(cudaStreamSynchronize(s), "pairs");
  std::printf("%s N=%d cavities=%d tile=%d: %d vertices, %d triangles, %d tiles, %d box blocks\n",
              argv[1], n, cavities, tile_side, m.vertices, m.triangles, tiles, m.reduce_blocks);
  std::printf("  binning: %ld (triangle, tile) pairs, %ld tiles with triangles\n", pairs, busy);
  auto report = [](const char* what, float us) { std::printf("  %-40s %7.2f us\n", what, us); };
  report("floor (1 empty kernel)", time_graph(s, [&] { empty_kernel<<<1, 32, 0, s>>>(); }));
  report("read (1 kernel: corners, a store each)",
         time_graph(s, [&] { launch(read_kernel, tri_blocks, s, false, m); }));
  report("touch (1 kernel, no box)",
         time_graph(s, [&] { launch(touch_kernel, tri_blocks, s, false, m); }));
  report("box + touch (2 kernels)", time_graph(s, [&] {
           launch(box_kernel, m.reduce_blocks, s, false, m);
           launch(setup_kernel<false>, tri_blocks, s, true, m);
         }));
  report("box + bin + tiles (3 kernels)", time_graph(s, [&] {
           launch(box_kernel, m.reduce_blocks, s, false, m);
           launch(setup_kernel<true>, tri_blocks, s, true, m);
           launch(tile_kernel, tiles, s, false, m);
         }));
  report("same, tiles overlapped", time_graph(s, [&] {
           launch(box_kernel, m.reduce_blocks, s, false, m);
           launch(setup_kernel<true>, tri_blocks, s, true, m);
           launch(tile_kernel, tiles, s, true, m);
         }));
  if (cavities == 1)
    report("box + hits + columns (3 kernels, plain port)", time_graph(s, [&] {
             launch(box_kernel, m.reduce_blocks, s, false, m);
             launch(hits_kernel, tri_blocks, s, true, m);
             launch(columns_kernel, (n * n + kBlock - 1) / kBlock, s, false, m);
           }));
  if (static_cast<double>(m.triangles) / cavities * tiles < 5e7)
    report("redundant (1 kernel, a block a tile)",
           time_graph(s, [&] { launch(redundant_kernel, tiles, s, false, m); }));
  char what[64];
  std::snprintf(what, sizeof what, "cooperative (1 kernel, %d blocks)", coop_blocks);
  report(what, time_graph(s, [&] {
           void* args[] = {&m};
           check(cudaLaunchCooperativeKernel(reinterpret_cast<void*>(cooperative_kernel),
                                             coop_blocks, kBlock, args, 0, s),
                 "cooperative launch");
         }));
  return 0;
}
