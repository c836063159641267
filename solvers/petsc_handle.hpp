// Owning handles for PETSc objects: the one place solvers/ and app/ release them, so that an
// exception (HS_PETSC, SolveError, Interrupted) can leave no object behind. The rule: no
// hand-written *Destroy in solvers/, app/ or tests/; hold what you create in one of these.
//
// A handle converts implicitly to the raw PETSc object, so it is passed to PETSc as is;
// creation functions write into `h.out()`, which releases what the handle held first. A handle
// holding nothing (a default one, or one whose creation failed) destroys nothing. Handles are
// move-only, so an object is released once. PETSc counts references: a KSP keeps its Mat alive,
// so the order in which handles go does not matter to PETSc. Every handle must go before
// PetscFinalize (app/main.cpp and tests/mpi_main.cpp finalize after the objects' scopes end).
#pragma once

#include <petscis.h>
#include <petscksp.h>
#include <petscmat.h>
#include <petscsf.h>
#include <petscsnes.h>
#include <petscvec.h>
#include <petscviewer.h>

#include <cstddef>
#include <utility>
#include <vector>

namespace hs {

template <typename T, PetscErrorCode (*Destroy)(T*)>
class PetscHandle {
 public:
  PetscHandle() noexcept = default;
  // Takes ownership of an object created elsewhere (e.g. Problem::create_vector).
  explicit PetscHandle(T raw) noexcept : raw_(raw) {}
  PetscHandle(PetscHandle&& other) noexcept : raw_(std::exchange(other.raw_, nullptr)) {}
  PetscHandle& operator=(PetscHandle&& other) noexcept {
    if (this != &other) {
      reset();
      raw_ = std::exchange(other.raw_, nullptr);
    }
    return *this;
  }
  PetscHandle(const PetscHandle&) = delete;
  PetscHandle& operator=(const PetscHandle&) = delete;
  // A Destroy error is ignored: a destructor may run while an exception unwinds, where a throw
  // would terminate the program, and nothing useful can be done with an object PETSc failed to
  // free (PETSc has already printed its own error trace).
  ~PetscHandle() { reset(); }

  operator T() const noexcept { return raw_; }
  T get() const noexcept { return raw_; }
  // For creation functions: `HS_PETSC(VecDuplicate(u, v.out()))`.
  T* out() noexcept {
    reset();
    return &raw_;
  }
  // Gives up ownership: the caller releases the object.
  T release() noexcept { return std::exchange(raw_, nullptr); }
  void reset() noexcept {
    if (raw_) (void)Destroy(&raw_);
    raw_ = nullptr;
  }

 private:
  T raw_ = nullptr;
};

using VecHandle = PetscHandle<Vec, VecDestroy>;
using MatHandle = PetscHandle<Mat, MatDestroy>;
using KspHandle = PetscHandle<KSP, KSPDestroy>;
using PcHandle = PetscHandle<PC, PCDestroy>;
using SnesHandle = PetscHandle<SNES, SNESDestroy>;
using LineSearchHandle = PetscHandle<SNESLineSearch, SNESLineSearchDestroy>;
using IsHandle = PetscHandle<IS, ISDestroy>;
using SfHandle = PetscHandle<PetscSF, PetscSFDestroy>;
using VecScatterHandle = PetscHandle<VecScatter, VecScatterDestroy>;
using MatPartitioningHandle = PetscHandle<MatPartitioning, MatPartitioningDestroy>;
using NullSpaceHandle = PetscHandle<MatNullSpace, MatNullSpaceDestroy>;
using ViewerHandle = PetscHandle<PetscViewer, PetscViewerDestroy>;

// A list of owned Vecs, kept as raw Vecs side by side because VecMDot and VecMAXPY take a Vec*
// (a vector of VecHandle is not one). Entries may be null (a constraint with no load).
class VecArray {
 public:
  VecArray() noexcept = default;
  VecArray(VecArray&& other) noexcept : vecs_(std::exchange(other.vecs_, {})) {}
  VecArray& operator=(VecArray&& other) noexcept {
    if (this != &other) {
      clear();
      vecs_ = std::exchange(other.vecs_, {});
    }
    return *this;
  }
  VecArray(const VecArray&) = delete;
  VecArray& operator=(const VecArray&) = delete;
  ~VecArray() { clear(); }  // Destroy errors ignored, as in PetscHandle

  // Takes ownership of v, also when the list cannot grow.
  void push_back(Vec v) {
    VecHandle owned(v);
    vecs_.push_back(nullptr);
    vecs_.back() = owned.release();
  }
  // Owns v in entry i, releasing what was there.
  void reset(std::size_t i, Vec v) noexcept {
    (void)VecDestroy(&vecs_[i]);
    vecs_[i] = v;
  }
  // New entries hold nothing; dropped entries are released.
  void resize(std::size_t n) {
    for (std::size_t i = n; i < vecs_.size(); ++i) (void)VecDestroy(&vecs_[i]);
    vecs_.resize(n, nullptr);
  }
  void clear() noexcept { resize(0); }

  Vec operator[](std::size_t i) const noexcept { return vecs_[i]; }
  Vec* data() noexcept { return vecs_.data(); }
  const Vec* data() const noexcept { return vecs_.data(); }
  std::size_t size() const noexcept { return vecs_.size(); }
  bool empty() const noexcept { return vecs_.empty(); }
  const Vec* begin() const noexcept { return vecs_.data(); }
  const Vec* end() const noexcept { return vecs_.data() + vecs_.size(); }

 private:
  std::vector<Vec> vecs_;
};

}  // namespace hs
