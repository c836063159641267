#include <cusolverSp.h>
#include <cusparse.h>

#include "gpu.hpp"
#include "methods.hpp"

Reordered reorder(const Csr& a, const std::string& ordering) {
  cusolverSpHandle_t h;
  cusparseMatDescr_t d;
  STATUS_CHECK(cusolverSpCreate(&h));
  STATUS_CHECK(cusparseCreateMatDescr(&d));
  STATUS_CHECK(cusparseSetMatType(d, CUSPARSE_MATRIX_TYPE_GENERAL));
  STATUS_CHECK(cusparseSetMatIndexBase(d, CUSPARSE_INDEX_BASE_ZERO));
  Reordered r;
  r.q.resize(a.n);
  const int n = a.n, nnz = a.nnz();
  if (ordering == "metis")
    STATUS_CHECK(cusolverSpXcsrmetisndHost(h, n, nnz, d, a.row_start.data(), a.column.data(),
                                           nullptr, r.q.data()));
  else if (ordering == "symamd")
    STATUS_CHECK(
        cusolverSpXcsrsymamdHost(h, n, nnz, d, a.row_start.data(), a.column.data(), r.q.data()));
  else if (ordering == "symrcm")
    STATUS_CHECK(
        cusolverSpXcsrsymrcmHost(h, n, nnz, d, a.row_start.data(), a.column.data(), r.q.data()));
  else
    throw std::runtime_error("unknown ordering " + ordering);
  r.row_start = a.row_start;
  r.column = a.column;
  r.map.resize(nnz);
  for (int k = 0; k < nnz; ++k) r.map[k] = k;
  size_t bytes = 0;
  STATUS_CHECK(cusolverSpXcsrperm_bufferSizeHost(h, n, n, nnz, d, r.row_start.data(),
                                                 r.column.data(), r.q.data(), r.q.data(), &bytes));
  std::vector<char> work(bytes + 1);
  STATUS_CHECK(cusolverSpXcsrpermHost(h, n, n, nnz, d, r.row_start.data(), r.column.data(),
                                      r.q.data(), r.q.data(), r.map.data(), work.data()));
  cusparseDestroyMatDescr(d);
  cusolverSpDestroy(h);
  return r;
}
