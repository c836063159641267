// Steps 3-4 inside one tile of TILE x TILE columns, shared by tile_kernel and fused_kernel.
//
// A round of triangles is staged in shared memory, each with its candidate rectangle (the
// columns of its box inside the tile) and its height plane there. An exclusive scan of the
// candidate counts lays all candidates of the round end to end, and each thread tests an
// equal, contiguous share of them, finding its first triangle by binary search (a
// load-balanced search). A triangle covering the whole tile and one covering a single column
// cost the same per candidate, whatever the mix. Hits go to per-column slots in shared memory
// (slot * TILE^2 + column), tagged with the triangle's item index (bitwise-negated for floors).
#pragma once

#include "device_common.cuh"

namespace fluidweight::detail::gpu {

// A round's triangles (structure of arrays: no bank conflicts). The height plane is set up
// once per triangle when it is staged: z0 at the first candidate (ci, cj) of its rectangle,
// dzi and dzj its steps along a row and a column. offset[k] is the first candidate of entry k
// (offset[m] the round's total).
template <typename Real, int N>
struct RasterStage {
  int x[3][N], y[3][N];
  int flags[N], ci[N], cj[N], width[N], offset[N + 1];
  Real z0[N], dzi[N], dzj[N];
};

// Height of the plane through the corners (x, y, z) at the centre of column (ci, cj), and its
// steps along a row (dzi) and a column (dzj): no division is left for the threads entering the
// triangle.
template <typename Real>
__device__ __forceinline__ void height_plane(const int (&x)[3], const int (&y)[3],
                                             const Real (&z)[3], int ci, int cj, int sub_bits,
                                             Real& z0, Real& dzi, Real& dzj) {
  const int px = column_centre(ci, sub_bits), py = column_centre(cj, sub_bits);
  Real area = 0;
  z0 = dzi = dzj = 0;
#pragma unroll
  for (int c = 0; c < 3; ++c) {
    const int p = (c + 1) % 3, q = (c + 2) % 3;
    const int64_t ec = edge_function(x[p], y[p], x[q], y[q], px, py);
    const int64_t di = -static_cast<int64_t>(y[q] - y[p]) << sub_bits;
    const int64_t dj = static_cast<int64_t>(x[q] - x[p]) << sub_bits;
    area += static_cast<Real>(ec);
    z0 += static_cast<Real>(ec) * z[c];
    dzi += static_cast<Real>(di) * z[c];
    dzj += static_cast<Real>(dj) * z[c];
  }
  const Real inv = Real(1) / area;
  z0 *= inv;
  dzi *= inv;
  dzj *= inv;
}

// Steps 3-4 of the staged entries [0, m) with `total` candidates, by the block's TILE^2
// threads: each tests an equal, contiguous share. Entry k's hits carry item tag_base + k.
template <typename Real, int TILE, int N>
__device__ __forceinline__ void raster_share(const RasterStage<Real, N>& s, int m, int total,
                                             int tag_base, int ti0, int tj0, int sub_bits,
                                             Real* s_z, int* s_tag, int* s_count, int capacity) {
  constexpr int kThreads = TILE * TILE;
  const int share = (total + kThreads - 1) / kThreads;
  int f = threadIdx.x * share;
  const int end = min(f + share, total);
  if (f >= end) return;
  int lo = 0, hi = m - 1;  // the last entry whose candidates start at or before f
  while (lo < hi) {
    int mid = (lo + hi + 1) >> 1;
    if (s.offset[mid] <= f) {
      lo = mid;
    } else {
      hi = mid - 1;
    }
  }
  // Walk the share; on each new triangle, its edge functions and height at the first
  // candidate and their steps along a row and at a row's end (exact integer steps).
  int item = lo - 1, next = s.offset[lo], li = 0, w = 1, col = 0, tag = 0;
  int64_t e[3], step[3], wrap[3], e_min[3];
  Real z = 0, dz = 0, dz_wrap = 0;
  for (; f < end; ++f) {
    if (f >= next) {
      do {
        ++item;
        next = s.offset[item + 1];
      } while (f >= next);
      // Entering a triangle: its edge functions at this candidate and their steps; the
      // height from the plane staged with it (no division, no 64-bit conversions).
      w = s.width[item];
      const int q0 = f - s.offset[item];
      // q0 < TILE^2 and w <= TILE: the float quotient is exact after truncation.
      const int lj =
          __float2int_rz(__fdividef(static_cast<float>(q0) + 0.5f, static_cast<float>(w)));
      li = q0 - lj * w;
      const int i = s.ci[item] + li, j = s.cj[item] + lj;
      const int px = column_centre(i, sub_bits), py = column_centre(j, sub_bits);
      const int flags = s.flags[item];
      for (int c = 0; c < 3; ++c) {
        const int p = (c + 1) % 3, q = (c + 2) % 3;
        const int xp = s.x[p][item], yp = s.y[p][item];
        const int xq = s.x[q][item], yq = s.y[q][item];
        e[c] = edge_function(xp, yp, xq, yq, px, py);
        step[c] = -static_cast<int64_t>(yq - yp) << sub_bits;
        wrap[c] = (static_cast<int64_t>(xq - xp) << sub_bits) - step[c] * (w - 1);
        e_min[c] = (flags >> c) & 1;
      }
      dz = s.dzi[item];
      const Real dzj = s.dzj[item];
      z = s.z0[item] + dz * static_cast<Real>(li) + dzj * static_cast<Real>(lj);
      dz_wrap = dzj - dz * static_cast<Real>(w - 1);
      col = (j - tj0) * TILE + (i - ti0);
      tag = is_floor(flags) ? ~(tag_base + item) : tag_base + item;
    }
    if (e[0] >= e_min[0] && e[1] >= e_min[1] && e[2] >= e_min[2]) {
      const int slot = atomicAdd(&s_count[col], 1);
      if (slot < capacity) {
        s_z[slot * kThreads + col] = z;
        s_tag[slot * kThreads + col] = tag;
      }
    }
    if (++li == w) {
      li = 0;
      col += TILE - (w - 1);
      z += dz_wrap;
      for (int c = 0; c < 3; ++c) e[c] += wrap[c];
    } else {
      col += 1;
      z += dz;
      for (int c = 0; c < 3; ++c) e[c] += step[c];
    }
  }
}

}  // namespace fluidweight::detail::gpu
