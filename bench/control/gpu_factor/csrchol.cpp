// cuSOLVER's sparse Cholesky on the GPU (the low-level csrchol API: symbolic analysis once,
// numeric factorization per step). It factors the pattern in the order given, so the
// tangent is reordered first (metis or symamd) and each step's values are gathered into the
// reordered pattern on the device.
#include <cusolverSp.h>
#include <cusolverSp_LOWLEVEL_PREVIEW.h>
#include <cusparse.h>

#include "gpu.hpp"
#include "methods.hpp"

Result run_csrchol(const Protocol& p, const std::string& ordering) {
  const Csr& a = *p.a;
  const int n = a.n, nnz = a.nnz();
  Result res;
  res.method = "cusolverSp csrchol (" + ordering + ")";
  double t0 = now_s();
  Reordered r = reorder(a, ordering);
  cudaStream_t s;
  CUDA_CHECK(cudaStreamCreate(&s));
  cusolverSpHandle_t h;
  cusparseMatDescr_t d;
  STATUS_CHECK(cusolverSpCreate(&h));
  STATUS_CHECK(cusolverSpSetStream(h, s));
  STATUS_CHECK(cusparseCreateMatDescr(&d));
  STATUS_CHECK(cusparseSetMatType(d, CUSPARSE_MATRIX_TYPE_GENERAL));
  STATUS_CHECK(cusparseSetMatIndexBase(d, CUSPARSE_INDEX_BASE_ZERO));
  DeviceArray<int> rp(n + 1), ci(nnz), map(nnz), q(n);
  DeviceArray<double> va(nnz), vb(nnz), b(n), bq(n), xq(n), x(n);
  CUDA_CHECK(cudaMemcpy(rp.p, r.row_start.data(), 4 * (n + 1), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(ci.p, r.column.data(), 4 * size_t(nnz), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(map.p, r.map.data(), 4 * size_t(nnz), cudaMemcpyHostToDevice));
  CUDA_CHECK(cudaMemcpy(q.p, r.q.data(), 4 * size_t(n), cudaMemcpyHostToDevice));
  csrcholInfo_t info;
  STATUS_CHECK(cusolverSpCreateCsrcholInfo(&info));
  STATUS_CHECK(cusolverSpXcsrcholAnalysis(h, n, nnz, d, rp.p, ci.p, info));
  size_t internal = 0, work_bytes = 0;
  CUDA_CHECK(cudaMemcpy(va.p, a.value.data(), 8 * size_t(nnz), cudaMemcpyHostToDevice));
  gather(vb.p, va.p, map.p, nnz, s);
  STATUS_CHECK(
      cusolverSpDcsrcholBufferInfo(h, n, nnz, d, vb.p, rp.p, ci.p, info, &internal, &work_bytes));
  DeviceArray<char> work(work_bytes);
  auto factor = [&](const std::vector<double>& v) {
    CUDA_CHECK(cudaMemcpyAsync(va.p, v.data(), 8 * size_t(nnz), cudaMemcpyHostToDevice, s));
    gather(vb.p, va.p, map.p, nnz, s);
    STATUS_CHECK(cusolverSpDcsrcholFactor(h, n, nnz, d, vb.p, rp.p, ci.p, info, work.p));
    int position = -1;  // the control loop must know at once when the tangent is not SPD
    STATUS_CHECK(cusolverSpDcsrcholZeroPivot(h, info, 1e-14, &position));
    CUDA_CHECK(cudaStreamSynchronize(s));
    if (position >= 0)
      throw std::runtime_error("csrchol: zero pivot at " + std::to_string(position));
  };
  std::vector<double> xh(n);
  auto solve = [&] {
    CUDA_CHECK(cudaMemcpyAsync(b.p, p.b.data(), 8 * size_t(n), cudaMemcpyHostToDevice, s));
    gather(bq.p, b.p, q.p, n, s);
    STATUS_CHECK(cusolverSpDcsrcholSolve(h, n, bq.p, xq.p, info, work.p));
    scatter(x.p, xq.p, q.p, n, s);
    CUDA_CHECK(cudaMemcpyAsync(xh.data(), x.p, 8 * size_t(n), cudaMemcpyDeviceToHost, s));
    CUDA_CHECK(cudaStreamSynchronize(s));
  };
  factor(a.value);
  solve();
  res.setup_ms = 1e3 * (now_s() - t0);
  time_repeats(
      p, factor, solve, [&] { return xh; }, res);
  cusolverSpDestroyCsrcholInfo(info);
  cusparseDestroyMatDescr(d);
  cusolverSpDestroy(h);
  cudaStreamDestroy(s);
  return res;
}
