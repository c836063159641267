// cusolverRf: refactorization with a fixed pattern and pivot sequence on the GPU. Its first
// LU comes from the host (cuSOLVER's csrlu on the reordered tangent, partial pivoting with
// the threshold given); each step then copies the new values in the tangent's own order
// (ResetValues applies P and Q on the device), refactors and solves.
#include <cusolverRf.h>
#include <cusolverSp.h>
#include <cusolverSp_LOWLEVEL_PREVIEW.h>
#include <cusparse.h>

#include "gpu.hpp"
#include "methods.hpp"

Result run_rf(const Protocol& p, const std::string& ordering, int factor_alg, int solve_alg) {
  const Csr& a = *p.a;
  const int n = a.n, nnz = a.nnz();
  Result res;
  res.method = "cusolverRf (" + ordering + ", algs " + std::to_string(factor_alg) + "/" +
               std::to_string(solve_alg) + ")";
  double t0 = now_s();
  Reordered r = reorder(a, ordering);
  std::vector<double> vb(nnz);
  for (int k = 0; k < nnz; ++k) vb[k] = a.value[r.map[k]];
  cusolverSpHandle_t h;
  cusparseMatDescr_t d;
  STATUS_CHECK(cusolverSpCreate(&h));
  STATUS_CHECK(cusparseCreateMatDescr(&d));
  STATUS_CHECK(cusparseSetMatType(d, CUSPARSE_MATRIX_TYPE_GENERAL));
  STATUS_CHECK(cusparseSetMatIndexBase(d, CUSPARSE_INDEX_BASE_ZERO));
  csrluInfoHost_t lu;
  STATUS_CHECK(cusolverSpCreateCsrluInfoHost(&lu));
  STATUS_CHECK(cusolverSpXcsrluAnalysisHost(h, n, nnz, d, r.row_start.data(), r.column.data(), lu));
  size_t internal = 0, bytes = 0;
  STATUS_CHECK(cusolverSpDcsrluBufferInfoHost(h, n, nnz, d, vb.data(), r.row_start.data(),
                                              r.column.data(), lu, &internal, &bytes));
  std::vector<char> work(bytes + 1);
  STATUS_CHECK(cusolverSpDcsrluFactorHost(h, n, nnz, d, vb.data(), r.row_start.data(),
                                          r.column.data(), lu, 1.0, work.data()));
  int singular = -1;
  STATUS_CHECK(cusolverSpDcsrluZeroPivotHost(h, lu, 1e-14, &singular));
  if (singular >= 0) throw std::runtime_error("csrlu: singular at " + std::to_string(singular));
  int nnz_l = 0, nnz_u = 0;
  STATUS_CHECK(cusolverSpXcsrluNnzHost(h, &nnz_l, &nnz_u, lu));
  res.nnz_factor = double(nnz_l) + nnz_u;
  std::vector<int> plu(n), qlu(n), lr(n + 1), lc(nnz_l), ur(n + 1), uc(nnz_u);
  std::vector<double> lv(nnz_l), uv(nnz_u);
  STATUS_CHECK(cusolverSpDcsrluExtractHost(h, plu.data(), qlu.data(), d, lv.data(), lr.data(),
                                           lc.data(), d, uv.data(), ur.data(), uc.data(), lu,
                                           work.data()));
  // P A Q^T = L U for the tangent itself: compose the pivoting with the reordering.
  std::vector<int> P(n), Q(n);
  for (int j = 0; j < n; ++j) P[j] = r.q[plu[j]], Q[j] = r.q[qlu[j]];
  cusolverRfHandle_t rf;
  STATUS_CHECK(cusolverRfCreate(&rf));
  STATUS_CHECK(cusolverRfSetNumericProperties(rf, 0.0, 0.0));
  STATUS_CHECK(cusolverRfSetAlgs(rf, cusolverRfFactorization_t(factor_alg),
                                 cusolverRfTriangularSolve_t(solve_alg)));
  STATUS_CHECK(cusolverRfSetMatrixFormat(rf, CUSOLVERRF_MATRIX_FORMAT_CSR,
                                         CUSOLVERRF_UNIT_DIAGONAL_ASSUMED_L));
  STATUS_CHECK(cusolverRfSetResetValuesFastMode(rf, CUSOLVERRF_RESET_VALUES_FAST_MODE_ON));
  std::vector<int> arp = a.row_start, aci = a.column;
  std::vector<double> av = a.value;
  STATUS_CHECK(cusolverRfSetupHost(n, nnz, arp.data(), aci.data(), av.data(), nnz_l, lr.data(),
                                   lc.data(), lv.data(), nnz_u, ur.data(), uc.data(), uv.data(),
                                   P.data(), Q.data(), rf));
  STATUS_CHECK(cusolverRfAnalyze(rf));
  DeviceArray<int> rp(n + 1), ci(nnz), dp(n), dq(n);
  DeviceArray<double> va(nnz), x(n), tmp(n);
  CUDA_CHECK(cudaMemcpy(rp.p, arp.data(), 4 * (n + 1), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(ci.p, aci.data(), 4 * size_t(nnz), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(dp.p, P.data(), 4 * size_t(n), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(dq.p, Q.data(), 4 * size_t(n), cudaMemcpyHostToDevice));
  // cusolverRf runs on the default stream: plain copies and a device synchronisation.
  auto factor = [&](const std::vector<double>& v) {
    CUDA_CHECK(cudaMemcpy(va.p, v.data(), 8 * size_t(nnz), cudaMemcpyHostToDevice));
    STATUS_CHECK(cusolverRfResetValues(n, nnz, rp.p, ci.p, va.p, dp.p, dq.p, rf));
    STATUS_CHECK(cusolverRfRefactor(rf));
    CUDA_CHECK(cudaDeviceSynchronize());
  };
  std::vector<double> xh(n);
  auto solve = [&] {
    CUDA_CHECK(cudaMemcpy(x.p, p.b.data(), 8 * size_t(n), cudaMemcpyHostToDevice));
    STATUS_CHECK(cusolverRfSolve(rf, dp.p, dq.p, 1, tmp.p, n, x.p, n));
    CUDA_CHECK(cudaMemcpy(xh.data(), x.p, 8 * size_t(n), cudaMemcpyDeviceToHost));
  };
  factor(a.value);
  solve();
  res.setup_ms = 1e3 * (now_s() - t0);
  time_repeats(
      p, factor, solve, [&] { return xh; }, res);
  cusolverRfDestroy(rf);
  cusolverSpDestroyCsrluInfoHost(lu);
  cusparseDestroyMatDescr(d);
  cusolverSpDestroy(h);
  return res;
}
