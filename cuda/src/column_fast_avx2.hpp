// Column method, CPU fast path: AVX2 forms of the hot kernels of column_fast_rows.hpp, for
// processors without AVX-512 (used by column_fast.cpp only). Boxes of one or two chunks of 8
// columns are rasterized with their edge functions in registers (two vectors of 4 lanes a
// chunk); covered lanes are written by blending into the planes (AVX2 has no byte or 64-bit
// lane masks; masked stores are slow on some processors), and rows are resolved 8 columns at a
// time where a column has at most one hit of each kind. Everything else (wide boxes, columns
// of several sections, set-ups) takes the portable kernels.
#pragma once

#include "column_fast_rows.hpp"

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__)) && \
    !defined(FLUIDWEIGHT_NO_AVX2)
#define FLUIDWEIGHT_AVX2 1
#include <immintrin.h>

namespace fluidweight::detail::rows {

#define FW_AVX2 __attribute__((target("avx2,bmi,popcnt")))

inline bool avx2_available() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2");
}

// All-ones lanes where bits of `bits` are set: 4 lanes of 64 bits, 8 of 32, 8 bytes.
FW_AVX2 inline __m256i lanes64(unsigned bits) {
  const __m256i b = _mm256_setr_epi64x(1, 2, 4, 8);
  return _mm256_cmpeq_epi64(_mm256_and_si256(_mm256_set1_epi64x(bits), b), b);
}
FW_AVX2 inline __m256i lanes32(unsigned bits) {
  const __m256i b = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  return _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(static_cast<int>(bits)), b), b);
}
FW_AVX2 inline __m128i lanes8(unsigned bits) {
  const __m128i b = _mm_setr_epi8(1, 2, 4, 8, 16, 32, 64, -128, 0, 0, 0, 0, 0, 0, 0, 0);
  return _mm_cmpeq_epi8(_mm_and_si128(_mm_set1_epi8(static_cast<char>(bits)), b), b);
}

// Lanes of 8 bytes equal to v, as 8 bits.
FW_AVX2 inline unsigned equal8(__m128i a, int v) {
  return static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(a, _mm_set1_epi8(v)))) & 0xFFu;
}

// Heights z (8 lanes as two halves) into plane p of a slot at lanes `k`, by blending.
template <bool kFloor>
FW_AVX2 inline void blend_plane(double* z, int* fl, unsigned k, const __m256d zv[2],
                                __m256i floor_index) {
  for (int h = 0; h < 2; ++h) {
    const __m256d old = _mm256_loadu_pd(z + 4 * h);
    _mm256_storeu_pd(z + 4 * h,
                     _mm256_blendv_pd(old, zv[h], _mm256_castsi256_pd(lanes64(k >> (4 * h)))));
  }
  if (kFloor) {
    const __m256i old = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(fl));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(fl),
                        _mm256_blendv_epi8(old, floor_index, lanes32(k)));
  }
}

// Hits of the chunk of columns col .. col + 7 (covered where bits of m are set) into the slot's
// planes, as write_chunk of the AVX-512 form; third and later hits lane by lane.
template <bool kFloor>
FW_AVX2 inline void write_chunk_avx2(const SlotView& v, size_t w, int col, unsigned m,
                                     const __m256d zv[2], __m256i floor_index,
                                     std::vector<Spilled>& spill, int floor, int column_offset) {
  const __m128i c = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(v.count + col));
  const unsigned k0 = equal8(c, 0) & m, k1 = equal8(c, 1) & m;
  blend_plane<kFloor>(v.z + col, v.floor + col, k0, zv, floor_index);
  if (k1) blend_plane<kFloor>(v.z + w + col, v.floor + w + col, k1, zv, floor_index);
  if (unsigned more = m & ~(k0 | k1)) {
    alignas(32) double zl[kChunk];
    _mm256_store_pd(zl, zv[0]);
    _mm256_store_pd(zl + 4, zv[1]);
    for (; more; more &= more - 1) {
      const int u = lowest_bit(more), i = col + u, n = v.count[i];
      if (n < kPlanes) {
        v.z[n * w + i] = zl[u];
        if (kFloor) v.floor[n * w + i] = floor;
      } else {
        spill.push_back({column_offset + i, floor, zl[u]});
      }
    }
  }
  _mm_storel_epi64(reinterpret_cast<__m128i*>(v.count + col),
                   _mm_adds_epu8(c, _mm_and_si128(lanes8(m), _mm_set1_epi8(1))));
}

template <bool kFloor, int kNarrow>
FW_AVX2 void raster_avx2_narrow(Raster& r, int rows, RowRing& ring) {
  constexpr int kind = kFloor ? 0 : 1;
  const size_t w = ring.width;
  __m256i v[kNarrow][2][3];
  __m256i step[3];
  for (int k = 0; k < 3; ++k) {
    step[k] = _mm256_set1_epi64x(r.dj[k]);
    for (int c = 0; c < kNarrow; ++c) {
      for (int h = 0; h < 2; ++h) {
        const int64_t u = kChunk * c + 4 * h;
        v[c][h][k] = _mm256_setr_epi64x(r.e[k] + r.di[k] * u, r.e[k] + r.di[k] * (u + 1),
                                        r.e[k] + r.di[k] * (u + 2), r.e[k] + r.di[k] * (u + 3));
      }
    }
  }
  __m256d zv[kNarrow][2];
  for (int c = 0; c < kNarrow; ++c) {
    for (int h = 0; h < 2; ++h) {
      const double u = kChunk * c + 4 * h;
      zv[c][h] = _mm256_add_pd(
          _mm256_set1_pd(r.z),
          _mm256_mul_pd(_mm256_set1_pd(r.dzi), _mm256_setr_pd(u, u + 1, u + 2, u + 3)));
    }
  }
  const __m256d zstep = _mm256_set1_pd(r.dzj);
  const __m256i floor_index = _mm256_set1_epi32(r.floor);
  const int i0 = r.i0, i1 = r.i1, floor = r.floor;
  uint8_t* const count = ring.count[kind].data() + i0;
  double* const zs = ring.z[kind].data() + i0;
  int* const fl = ring.floor.data() + i0;
  int row = r.row;
  for (int q = 0; q < rows; ++q, ++row) {
    const int slot = row & (ring.rows - 1);
    const SlotView sv{count + slot * w, zs + slot * kPlanes * w, fl + slot * kPlanes * w};
    for (int c = 0; c < kNarrow; ++c) {
      unsigned negative = 0;
      for (int h = 0; h < 2; ++h) {
        const __m256i any = _mm256_or_si256(_mm256_or_si256(v[c][h][0], v[c][h][1]), v[c][h][2]);
        negative |= static_cast<unsigned>(_mm256_movemask_pd(_mm256_castsi256_pd(any))) << (4 * h);
        for (int k = 0; k < 3; ++k) v[c][h][k] = _mm256_add_epi64(v[c][h][k], step[k]);
      }
      write_chunk_avx2<kFloor>(sv, w, kChunk * c, ~negative & 0xFFu, zv[c], floor_index,
                               ring.spill[kind][slot], floor, i0);
      for (int h = 0; h < 2; ++h) zv[c][h] = _mm256_add_pd(zv[c][h], zstep);
    }
    ring.lo[slot] = std::min(ring.lo[slot], i0);
    ring.hi[slot] = std::max(ring.hi[slot], i1);
  }
  for (int k = 0; k < 3; ++k) r.e[k] += r.dj[k] * rows;
  r.z += r.dzj * rows;
  r.row = row;
}

// Boxes of three chunks or more: each row's span by division first, then its chunks.
template <bool kFloor>
FW_AVX2 void raster_avx2_wide(Raster& r, int rows, RowRing& ring) {
  constexpr int kind = kFloor ? 0 : 1;
  const size_t w = ring.width;
  const __m256i quad = _mm256_setr_epi64x(0, 1, 2, 3);
  __m256i lane[2][3], step[3];
  for (int k = 0; k < 3; ++k) {
    // di u for u = 0..7 (exact: |di| 7 < 2^43).
    const __m256i di = _mm256_set1_epi64x(r.di[k]);
    __m256i m = _mm256_setzero_si256();
    for (int u = 1; u < 4; ++u) {
      m = _mm256_add_epi64(
          m, _mm256_and_si256(di, _mm256_cmpgt_epi64(quad, _mm256_set1_epi64x(u - 1))));
    }
    lane[0][k] = m;
    lane[1][k] = _mm256_add_epi64(m, _mm256_set1_epi64x(4 * r.di[k]));
    step[k] = _mm256_set1_epi64x(kChunk * r.di[k]);
  }
  const __m256d lane_z[2] = {_mm256_mul_pd(_mm256_set1_pd(r.dzi), _mm256_setr_pd(0, 1, 2, 3)),
                             _mm256_mul_pd(_mm256_set1_pd(r.dzi), _mm256_setr_pd(4, 5, 6, 7))};
  const __m256i floor_index = _mm256_set1_epi32(r.floor);
  for (int q = 0; q < rows; ++q, ++r.row) {
    int first, last;
    if (wide_span(r, first, last)) {
      const int slot = r.row & (ring.rows - 1);
      const SlotView sv{ring.count[kind].data() + slot * w,
                        ring.z[kind].data() + slot * kPlanes * w,
                        ring.floor.data() + slot * kPlanes * w};
      __m256i v[2][3];
      for (int h = 0; h < 2; ++h) {
        for (int k = 0; k < 3; ++k) {
          v[h][k] =
              _mm256_add_epi64(_mm256_set1_epi64x(r.e[k] + r.di[k] * (first - r.i0)), lane[h][k]);
        }
      }
      for (int col = first; col <= last; col += kChunk) {
        unsigned negative = 0;
        for (int h = 0; h < 2; ++h) {
          const __m256i any = _mm256_or_si256(_mm256_or_si256(v[h][0], v[h][1]), v[h][2]);
          negative |= static_cast<unsigned>(_mm256_movemask_pd(_mm256_castsi256_pd(any)))
                      << (4 * h);
          for (int k = 0; k < 3; ++k) v[h][k] = _mm256_add_epi64(v[h][k], step[k]);
        }
        const __m256d zc = _mm256_set1_pd(r.z + r.dzi * (col - r.i0));
        const __m256d zv[2] = {_mm256_add_pd(zc, lane_z[0]), _mm256_add_pd(zc, lane_z[1])};
        write_chunk_avx2<kFloor>(sv, w, col, ~negative & 0xFFu, zv, floor_index,
                                 ring.spill[kind][slot], r.floor, 0);
      }
      ring.lo[slot] = std::min(ring.lo[slot], first);
      ring.hi[slot] = std::max(ring.hi[slot], last);
    }
    for (int k = 0; k < 3; ++k) r.e[k] += r.dj[k];
    r.z += r.dzj;
  }
}

FW_AVX2 inline void raster_avx2(Raster& r, int rows, RowRing& ring) {
  const int chunks = (r.i1 - r.i0) / kChunk + 1;
  if (chunks > 2) {
    if (r.floor >= 0) return raster_avx2_wide<true>(r, rows, ring);
    return raster_avx2_wide<false>(r, rows, ring);
  }
  if (r.floor >= 0) {
    if (chunks == 1) return raster_avx2_narrow<true, 1>(r, rows, ring);
    return raster_avx2_narrow<true, 2>(r, rows, ring);
  }
  if (chunks == 1) return raster_avx2_narrow<false, 1>(r, rows, ring);
  raster_avx2_narrow<false, 2>(r, rows, ring);
}

FW_AVX2 inline double sum4(__m256d v) {
  const __m128d s = _mm_add_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
  return _mm_cvtsd_f64(_mm_add_sd(s, _mm_unpackhi_pd(s, s)));
}

// Resolution of row j: chunks of 8 columns with at most one hit of each kind at once (one
// update of the floor's moments when the chunk's sections share their floor), the others
// column by column as the portable resolution does.
FW_AVX2 inline void resolve_avx2(int j, RowRing& ring, FloorMoments* moments, ColumnScratch& s,
                                 RowTotals& totals) {
  int slot, lo, hi;
  if (!take_row(j, ring, slot, lo, hi)) return;
  const size_t w = ring.width;
  uint8_t *fc = ring.count[0].data() + slot * w, *cc = ring.count[1].data() + slot * w;
  const double* fz = ring.z[0].data() + slot * kPlanes * w;
  const double* cz = ring.z[1].data() + slot * kPlanes * w;
  const int* fl = ring.floor.data() + slot * kPlanes * w;
  const __m128i one = _mm_set1_epi8(1);
  const __m256d lane = _mm256_setr_pd(0, 1, 2, 3);
  size_t at[2] = {0, 0};
  for (int col = lo & ~(kChunk - 1); col <= hi; col += kChunk) {
    const __m128i f = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(fc + col));
    const __m128i c = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(cc + col));
    const __m128i both = _mm_or_si128(f, c);
    const unsigned empty = equal8(both, 0);
    if (empty == 0xFFu) continue;
    // Lanes with at most one hit of each kind: min(both, 1) == both.
    const unsigned single =
        static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(_mm_min_epu8(both, one), both))) &
        0xFFu;
    if (single != 0xFFu) {
      for (int i = col; i < col + kChunk; ++i)
        resolve_one(slot, i, j, ring, at, moments, s, totals);
      continue;
    }
    const unsigned m = equal8(_mm_and_si128(f, c), 1);
    totals.unmatched += _mm_popcnt_u32(~equal8(_mm_cmpeq_epi8(f, c), 0xFF) & 0xFFu);
    _mm_storel_epi64(reinterpret_cast<__m128i*>(fc + col), _mm_setzero_si128());
    _mm_storel_epi64(reinterpret_cast<__m128i*>(cc + col), _mm_setzero_si128());
    if (!m) continue;
    __m256d h[2];
    double s0 = 0.0;
    for (int k = 0; k < 2; ++k) {
      h[k] = _mm256_and_pd(
          _mm256_sub_pd(_mm256_loadu_pd(cz + col + 4 * k), _mm256_loadu_pd(fz + col + 4 * k)),
          _mm256_castsi256_pd(lanes64(m >> (4 * k))));
    }
    const int leader = fl[col + lowest_bit(m)];
    const __m256i floors = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(fl + col));
    const unsigned same = static_cast<unsigned>(_mm256_movemask_ps(_mm256_castsi256_ps(
                              _mm256_cmpeq_epi32(floors, _mm256_set1_epi32(leader))))) &
                          m;
    if (same == m) {
      s0 = sum4(_mm256_add_pd(h[0], h[1]));
      const double s1 = sum4(_mm256_add_pd(
          _mm256_mul_pd(h[0], lane), _mm256_mul_pd(h[1], _mm256_add_pd(lane, _mm256_set1_pd(4)))));
      FloorMoments& r = moments[leader];
      r.m0 += s0;
      r.mi += s1 + s0 * col;
      r.mj += s0 * j;
    } else {
      for (unsigned b = m; b; b &= b - 1) {
        const int i = col + lowest_bit(b);
        const double hi_ = cz[i] - fz[i];
        add_section(moments[fl[i]], hi_, i, j);
        s0 += hi_;
      }
    }
    totals.sum_heights += s0;
  }
  ring.spill[0][slot].clear();
  ring.spill[1][slot].clear();
}

}  // namespace fluidweight::detail::rows

#endif
