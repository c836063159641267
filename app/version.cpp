#include "version.hpp"

#include <H5public.h>
#include <dmumps_c.h>
#include <gmsh.h>
#include <mpi.h>
#include <petscversion.h>
#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <sstream>

#include "fluidweight/fluidweight.hpp"
#include "git_commit.hpp"  // generated at build time: kGitCommit

namespace hs {

std::string version_text() {
  std::ostringstream s;
  s << "hydrosoft " << HYDROSOFT_VERSION << " (commit " << kGitCommit << ")\n";
  s << "PETSc " << PETSC_VERSION_MAJOR << "." << PETSC_VERSION_MINOR << "."
    << PETSC_VERSION_SUBMINOR << ", MUMPS " << MUMPS_VERSION << ", gmsh API " << GMSH_API_VERSION
    << ", HDF5 " << H5_VERS_MAJOR << "." << H5_VERS_MINOR << "." << H5_VERS_RELEASE << ", Eigen "
    << EIGEN_WORLD_VERSION << "." << EIGEN_MAJOR_VERSION << "." << EIGEN_MINOR_VERSION << "\n";
  char mpi[MPI_MAX_LIBRARY_VERSION_STRING];
  int length = 0;
  MPI_Get_library_version(mpi, &length);  // allowed before MPI_Init
  std::string library(mpi, length);
  s << "MPI: " << library.substr(0, library.find_first_of(",\n")) << "\n";
  const std::string device = fluidweight::cuda_device_name();
  s << "CUDA: "
    << (fluidweight::cuda_available() ? "fluid weight on " + device
                                      : "none (not built in, or no device)")
    << "\n";
  return s.str();
}

}  // namespace hs
