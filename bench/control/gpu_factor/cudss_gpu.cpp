// cuDSS, the sparse direct solver that replaces cuSOLVER's sparse routines (a library of
// its own, outside the toolkit; built only when its header and library are found).
// Analysis once, a numeric refactorization per step, the values copied in place.
#include <cudss.h>

#include "gpu.hpp"
#include "methods.hpp"

Result run_cudss(const Protocol& p, bool spd) {
  const Csr& a = *p.a;
  const int n = a.n, nnz = a.nnz();
  Result res;
  res.method = spd ? "cuDSS Cholesky (SPD)" : "cuDSS L D L^T (symmetric)";
  double t0 = now_s();
  cudaStream_t s;
  CUDA_CHECK(cudaStreamCreate(&s));
  cudssHandle_t h;
  cudssConfig_t config;
  cudssData_t data;
  STATUS_CHECK(cudssCreate(&h));
  STATUS_CHECK(cudssSetStream(h, s));
  STATUS_CHECK(cudssConfigCreate(&config));
  STATUS_CHECK(cudssDataCreate(h, &data));
  DeviceArray<int> rp(n + 1), ci(nnz);
  DeviceArray<double> va(nnz), b(n), x(n);
  CUDA_CHECK(cudaMemcpy(rp.p, a.row_start.data(), 4 * (n + 1), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(ci.p, a.column.data(), 4 * size_t(nnz), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(va.p, a.value.data(), 8 * size_t(nnz), cudaMemcpyHostToDevice));
  cudssMatrix_t A, B, X;
  const auto mtype = spd ? CUDSS_MTYPE_SPD : CUDSS_MTYPE_SYMMETRIC;
#if defined(CUDSS_VERSION) && CUDSS_VERSION >= 800
  STATUS_CHECK(cudssMatrixCreateCsr(&A, n, n, nnz, rp.p, nullptr, ci.p, va.p, CUDA_R_32I,
                                    CUDA_R_32I, CUDA_R_64F, mtype, CUDSS_MVIEW_FULL,
                                    CUDSS_BASE_ZERO));
#else
  STATUS_CHECK(cudssMatrixCreateCsr(&A, n, n, nnz, rp.p, nullptr, ci.p, va.p, CUDA_R_32I,
                                    CUDA_R_64F, mtype, CUDSS_MVIEW_FULL, CUDSS_BASE_ZERO));
#endif
  STATUS_CHECK(cudssMatrixCreateDn(&B, n, 1, n, b.p, CUDA_R_64F, CUDSS_LAYOUT_COL_MAJOR));
  STATUS_CHECK(cudssMatrixCreateDn(&X, n, 1, n, x.p, CUDA_R_64F, CUDSS_LAYOUT_COL_MAJOR));
  CUDA_CHECK(cudaMemcpy(b.p, p.b.data(), 8 * size_t(n), cudaMemcpyHostToDevice));
  STATUS_CHECK(cudssExecute(h, CUDSS_PHASE_ANALYSIS, config, data, A, X, B));
  STATUS_CHECK(cudssExecute(h, CUDSS_PHASE_FACTORIZATION, config, data, A, X, B));
  auto factor = [&](const std::vector<double>& v) {
    CUDA_CHECK(cudaMemcpyAsync(va.p, v.data(), 8 * size_t(nnz), cudaMemcpyHostToDevice, s));
    STATUS_CHECK(cudssExecute(h, CUDSS_PHASE_REFACTORIZATION, config, data, A, X, B));
    CUDA_CHECK(cudaStreamSynchronize(s));
  };
  std::vector<double> xh(n);
  auto solve = [&] {
    CUDA_CHECK(cudaMemcpyAsync(b.p, p.b.data(), 8 * size_t(n), cudaMemcpyHostToDevice, s));
    STATUS_CHECK(cudssExecute(h, CUDSS_PHASE_SOLVE, config, data, A, X, B));
    CUDA_CHECK(cudaMemcpyAsync(xh.data(), x.p, 8 * size_t(n), cudaMemcpyDeviceToHost, s));
    CUDA_CHECK(cudaStreamSynchronize(s));
  };
  factor(a.value);
  solve();
  res.setup_ms = 1e3 * (now_s() - t0);
  int64_t lu_nnz = 0;
  size_t written = 0;
  if (cudssDataGet(h, data, CUDSS_DATA_LU_NNZ, &lu_nnz, sizeof lu_nnz, &written) == 0)
    res.nnz_factor = double(lu_nnz);
  std::vector<double> tf, ts;
  for (int k = 0; k < p.repeats; ++k) {
    const auto& v = p.sets[k % p.sets.size()];
    double t = now_s();
    factor(v);
    tf.push_back(now_s() - t);
    t = now_s();
    solve();
    ts.push_back(now_s() - t);
    if (k == p.repeats - 1) res.relres = relative_residual(a, v.data(), p.b, xh);
  }
  res.factor_ms = 1e3 * median(tf);
  res.solve_ms = 1e3 * median(ts);
  cudssMatrixDestroy(A);
  cudssMatrixDestroy(B);
  cudssMatrixDestroy(X);
  cudssDataDestroy(h, data);
  cudssConfigDestroy(config);
  cudssDestroy(h);
  cudaStreamDestroy(s);
  return res;
}
