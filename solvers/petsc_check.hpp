// Turns a PETSc error code into a C++ exception. (PETSc's own PetscCallThrow exists only in
// PETSc builds configured for C++; Debian's is built for C.)
#pragma once

#include <petscsys.h>

#include <stdexcept>
#include <string>

namespace hs {

[[noreturn]] inline void throw_petsc_error(PetscErrorCode code, const char* file, int line) {
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw std::runtime_error(std::string("PETSc error ") + std::to_string(static_cast<int>(code)) +
                           " (" + (text ? text : "unknown") + ") at " + file + ":" +
                           std::to_string(line));
}

}  // namespace hs

#define HS_PETSC(...)                                                                             \
  do {                                                                                            \
    const PetscErrorCode hs_petsc_code_ = (__VA_ARGS__);                                          \
    if (PetscUnlikely(hs_petsc_code_)) hs::throw_petsc_error(hs_petsc_code_, __FILE__, __LINE__); \
  } while (0)
