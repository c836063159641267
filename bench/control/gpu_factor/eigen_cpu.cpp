// A CPU baseline that runs on the GPU machine too (no PETSc, MUMPS or CHOLMOD there):
// Eigen's simplicial L L^T or L D L^T with AMD, pattern analysed once. It is not
// supernodal, so it is slower than MUMPS and CHOLMOD; run here and on the development
// machine it gives the ratio between the two machines' cores.
#include <Eigen/SparseCholesky>

#include "methods.hpp"

namespace {

template <class Solver>
Result run(const Protocol& p, const char* name) {
  const Csr& a = *p.a;
  Result res;
  res.method = name;
  // The tangent is symmetric: its CSR arrays are also its CSC arrays.
  auto view = [&](const std::vector<double>& v) {
    return Eigen::Map<const Eigen::SparseMatrix<double, Eigen::ColMajor, int>>(
        a.n, a.n, a.nnz(), a.row_start.data(), a.column.data(), v.data());
  };
  Eigen::Map<const Eigen::VectorXd> b(p.b.data(), a.n);
  double t0 = now_s();
  Solver solver;
  solver.analyzePattern(view(a.value));
  solver.factorize(view(a.value));
  if (solver.info() != Eigen::Success) throw std::runtime_error(std::string(name) + " failed");
  Eigen::VectorXd x = solver.solve(b);
  res.setup_ms = 1e3 * (now_s() - t0);
  res.nnz_factor = double(solver.matrixL().nestedExpression().nonZeros());
  auto factor = [&](const std::vector<double>& v) {
    solver.factorize(view(v));
    if (solver.info() != Eigen::Success) throw std::runtime_error(std::string(name) + " failed");
  };
  auto solution = [&] { return std::vector<double>(x.data(), x.data() + a.n); };
  time_repeats(
      p, factor, [&] { x = solver.solve(b); }, solution, res);
  return res;
}

}  // namespace

Result run_eigen(const Protocol& p, bool ldlt) {
  using M = Eigen::SparseMatrix<double>;
  if (ldlt)
    return run<Eigen::SimplicialLDLT<M, Eigen::Lower, Eigen::AMDOrdering<int>>>(
        p, "Eigen SimplicialLDLT (AMD), CPU");
  return run<Eigen::SimplicialLLT<M, Eigen::Lower, Eigen::AMDOrdering<int>>>(
      p, "Eigen SimplicialLLT (AMD), CPU");
}
