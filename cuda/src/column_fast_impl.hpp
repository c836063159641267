// The CPU fast path's state and buffers, shared by its set-up (column_fast.cpp: Steps 1-2, the
// sort by rows, the bands) and its sweep (column_fast_sweep.cpp). Internal to the module.
#pragma once

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <limits>

#include "column_fast_avx2.hpp"
#include "column_fast_avx512.hpp"
#include "cpu.hpp"
#include "thread_pool.hpp"

namespace fluidweight::detail {

using rows::FloorMoments;
using rows::Raster;

constexpr int kPrefetch = 24;       // triangles whose vertices are asked for ahead of their setup
constexpr int kPrefetchAhead = 16;  // the same, in the passes of Steps 1 and 2 over the triangles
constexpr int kMaxRingRows = 16;    // rows a triangle is rasterized at once, at most
constexpr size_t kRingBytes = 4 << 20;  // and the ring's size, at most

// A vertex after Step 1: snapped coordinates and height above the lowest vertex.
struct SnappedVertex {
  int x, y;
  double z;
};

// A vertex as Step 2 reads it: snapped coordinates, and frame coordinates relative to the
// grid's corner for the signed volume, summed in the same pass (its gathers of three vertices a
// triangle are those of Step 2). 32 bytes, aligned: a vertex is one load, within a cache line.
struct alignas(32) Step2Vertex {
  int x, y;
  double a, b, u;
};

// A triangle with columns after Step 2, in first-row order: its vertices counter-clockwise and
// flags. 16 bytes: the sweep reads them one after another and gathers the vertices (a
// triangle's vertices are near each other in memory, and there are half as many).
struct SortedTriangle {
  int vertex[3];
  unsigned flags;  // bit k (0-2): e_min[k] = 1, the edge is neither top nor left; bit 3: a floor
};

// What a floor needs at the end to turn its moments into nodal weights: its edge functions at
// its origin (twice the area times the barycentric coordinates there) and their steps.
struct FloorSetup {
  int64_t e[3];
  int dx[3], dy[3];
  int triangle;  // in `sorted`
  int i0, j0;    // the origin
};

// Buffers of one worker thread, kept between calls.
struct Worker {
  rows::RowRing ring;
  // Per floor rasterized in the band, the first `floors` (sized once for the band: no
  // capacity check per triangle).
  std::vector<FloorMoments> moments;
  std::vector<FloorSetup> setups;
  int floors = 0;
  std::vector<std::vector<Raster>> pending;  // per ring slot: tall triangles going on there
  std::vector<Raster> taken;
  rows::ColumnScratch scratch;
#if defined(FLUIDWEIGHT_AVX512)
  rows::SetupBatch batch;
#endif
  std::vector<double> weights;  // one per vertex
  rows::RowTotals totals;
};

inline void prefetch(const void* p) {
#if defined(__GNUC__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

struct FastColumn::Impl {
  Impl(int threads, CpuKernels kernels);

  void sweep_band(int band, Worker& w);
  void start(int t, int j, int jb, Worker& w);
  void start_row(int j, int jb, Worker& w);
  template <class Kernel>
  void raster_block(Raster& r, int jb, Worker& w, Kernel kernel);
  void raster_block(Raster& r, int jb, Worker& w) { raster_block(r, jb, w, raster); }
  void finish_floors(Worker& w);

  ThreadPool pool;
  std::vector<Worker> workers;
  bool avx512 = false;
  void (*raster)(Raster&, int, rows::RowRing&) = rows::raster_portable;
  void (*resolve)(int, rows::RowRing&, FloorMoments*, rows::ColumnScratch&,
                  rows::RowTotals&) = rows::resolve_portable;
  // The call's grid, and per vertex its snapped coordinates and height.
  GridParams grid;
  double rho_g = 0.0;
  std::vector<SnappedVertex> vertices;
  std::vector<Step2Vertex> step2_vertices;
  std::vector<int> row0;  // first row of each triangle's box, -1: no column
  // SortedTriangle::flags, and bit 4: corners 1 and 2 swapped; bits 5-6: box chunks - 1, at
  // most 2 (the raster kernel's class)
  std::vector<unsigned> flags;
  // Triangles with columns by first row: those of row j are sorted[row_start[j] ..
  // row_start[j + 1]).
  std::vector<int> row_start;
  std::vector<int> bucket_start;  // the counting sort's, by row and class
  std::vector<SortedTriangle> sorted;
  // Bands: rows [b band_rows, (b + 1) band_rows); triangles starting in an earlier band and
  // reaching band b are carried[carried_start[b] .. carried_start[b + 1]).
  std::vector<int> carried_start, carried;
  int band_rows = 1, num_bands = 1;
  int ring_rows = 1;       // rows a triangle is rasterized at once
  bool automatic_threads;  // threads = 0: all of them, but one for small problems
  // Step 2's orientation is assumed per cavity (by its triangle array) to be the one its
  // previous call found, +1 at first, so that the signed volume can be summed in Step 2's pass;
  // Step 2 is run again where the sign disagrees (a cavity turned inside out).
  std::vector<std::pair<const int*, int>> orientations;
  int& orientation_of(const int* triangles) {
    for (auto& o : orientations) {
      if (o.first == triangles) return o.second;
    }
    if (orientations.size() >= 64) orientations.clear();  // contexts re-created cavities
    orientations.push_back({triangles, 1});
    return orientations.back().second;
  }
};

}  // namespace fluidweight::detail
