// The tangent as plain CSR, read from PETSc's binary format (what -ksp_view_mat binary:K.bin
// writes), so that this benchmark needs neither PETSc nor MPI on the GPU machine.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

struct Csr {
  int n = 0;
  std::vector<int> row_start, column;
  std::vector<double> value;
  int nnz() const { return static_cast<int>(column.size()); }
};

// PETSc writes big-endian: class id, rows, columns, nonzeros, row lengths, columns, values.
// Only the first matrix of the file is read (a run with ::append may write several).
inline Csr read_petsc_binary(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw std::runtime_error("cannot open " + path);
  auto be32 = [&](int count, int* out) {
    std::vector<unsigned char> b(4 * static_cast<size_t>(count));
    if (std::fread(b.data(), 1, b.size(), f) != b.size()) throw std::runtime_error("short read");
    for (int i = 0; i < count; ++i)
      out[i] = static_cast<int>(uint32_t(b[4 * i]) << 24 | uint32_t(b[4 * i + 1]) << 16 |
                                uint32_t(b[4 * i + 2]) << 8 | uint32_t(b[4 * i + 3]));
  };
  int head[4];
  be32(4, head);
  if (head[0] != 1211216 || head[1] != head[2]) throw std::runtime_error("not a square PETSc Mat");
  Csr a;
  a.n = head[1];
  std::vector<int> len(a.n);
  be32(a.n, len.data());
  a.row_start.assign(a.n + 1, 0);
  for (int i = 0; i < a.n; ++i) a.row_start[i + 1] = a.row_start[i] + len[i];
  a.column.resize(head[3]);
  be32(head[3], a.column.data());
  std::vector<unsigned char> b(8 * static_cast<size_t>(head[3]));
  if (std::fread(b.data(), 1, b.size(), f) != b.size()) throw std::runtime_error("short read");
  std::fclose(f);
  a.value.resize(head[3]);
  for (size_t k = 0; k < a.value.size(); ++k) {
    uint64_t u = 0;
    for (int j = 0; j < 8; ++j) u = u << 8 | b[8 * k + j];
    std::memcpy(&a.value[k], &u, 8);
  }
  return a;
}

// Value sets with the tangent's pattern, each entry scaled by 1 + 1e-6 r with r in [-1, 1]
// the same for (i, j) and (j, i): new numbers every step, as a control step brings, that keep
// the matrix symmetric and (at this size of change) as definite as it was. Rotating among a
// few sets keeps a library from meeting the values it has just seen.
inline std::vector<std::vector<double>> perturbed_sets(const Csr& a, int count) {
  std::vector<std::vector<double>> sets(count, a.value);
  for (int s = 0; s < count; ++s)
    for (int i = 0; i < a.n; ++i)
      for (int k = a.row_start[i]; k < a.row_start[i + 1]; ++k) {
        uint64_t lo = std::min(i, a.column[k]), hi = std::max(i, a.column[k]);
        uint64_t h = (lo * 0x9E3779B97F4A7C15ull) ^ (hi + 0x632BE59BD9B4E019ull * (s + 1));
        h ^= h >> 31;
        h *= 0xBF58476D1CE4E5B9ull;
        h ^= h >> 29;
        double r = static_cast<double>(h >> 11) / 9007199254740992.0 * 2 - 1;
        sets[s][k] *= 1 + 1e-6 * r;
      }
  return sets;
}

// |b - A x| / |b| with the values v on A's pattern.
inline double relative_residual(const Csr& a, const double* v, const std::vector<double>& b,
                                const std::vector<double>& x) {
  double rr = 0, bb = 0;
  for (int i = 0; i < a.n; ++i) {
    double s = b[i];
    for (int k = a.row_start[i]; k < a.row_start[i + 1]; ++k) s -= v[k] * x[a.column[k]];
    rr += s * s;
    bb += b[i] * b[i];
  }
  return std::sqrt(rr / bb);
}

inline double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

inline double median(std::vector<double> v) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

// One method's figures, in milliseconds (medians over the repeats).
struct Result {
  std::string method;
  double setup_ms = NAN;    // ordering, analysis and first factorization, once per pattern
  double factor_ms = NAN;   // values host -> device + numeric factorization, per step
  double upload_ms = NAN;   // of which the values' copy alone
  double solve_ms = NAN;    // right-hand side host -> device, solve, solution device -> host
  double relres = NAN;      // |b - A x| / |b| of the last solve
  double nnz_factor = NAN;  // entries of L (or L + U)
};
