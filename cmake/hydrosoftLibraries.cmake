# gmsh, CHOLMOD and Scotch ship no CMake or pkg-config files on Debian 12 (libseccomp, which
# confines gmsh's process, ships pkg-config only). Each becomes an imported target here
# (hydrosoft_dep::gmsh, ::cholmod, ::scotch, ::seccomp), found the same way by the
# build and by an installed hydrosoftConfig.cmake, so that the exported targets name them and
# carry no absolute paths of the machine that built them.
# Sets HYDROSOFT_LIBRARIES_MISSING to the names not found (empty when all are).
find_path(GMSH_INCLUDE_DIR gmsh.h)
find_library(GMSH_LIBRARY gmsh)
find_library(CHOLMOD_LIBRARY cholmod)
find_library(SCOTCH_LIBRARY scotch)
find_path(SECCOMP_INCLUDE_DIR seccomp.h)
find_library(SECCOMP_LIBRARY seccomp)

set(HYDROSOFT_LIBRARIES_MISSING "")
foreach(variable GMSH_INCLUDE_DIR GMSH_LIBRARY CHOLMOD_LIBRARY SCOTCH_LIBRARY
                 SECCOMP_INCLUDE_DIR SECCOMP_LIBRARY)
  if(NOT ${variable})
    list(APPEND HYDROSOFT_LIBRARIES_MISSING ${variable})
  endif()
endforeach()

if(NOT HYDROSOFT_LIBRARIES_MISSING AND NOT TARGET hydrosoft_dep::gmsh)
  add_library(hydrosoft_dep::gmsh UNKNOWN IMPORTED)
  set_target_properties(hydrosoft_dep::gmsh PROPERTIES IMPORTED_LOCATION "${GMSH_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${GMSH_INCLUDE_DIR}")
  add_library(hydrosoft_dep::cholmod UNKNOWN IMPORTED)
  set_target_properties(hydrosoft_dep::cholmod PROPERTIES IMPORTED_LOCATION "${CHOLMOD_LIBRARY}")
  add_library(hydrosoft_dep::scotch UNKNOWN IMPORTED)
  set_target_properties(hydrosoft_dep::scotch PROPERTIES IMPORTED_LOCATION "${SCOTCH_LIBRARY}")
  add_library(hydrosoft_dep::seccomp UNKNOWN IMPORTED)
  set_target_properties(hydrosoft_dep::seccomp PROPERTIES IMPORTED_LOCATION "${SECCOMP_LIBRARY}"
                        INTERFACE_INCLUDE_DIRECTORIES "${SECCOMP_INCLUDE_DIR}")
endif()
