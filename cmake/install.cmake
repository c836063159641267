# What `cmake --install BUILD --prefix P` puts under P (the fluid-weight module installs its
# own part and package: cuda/CMakeLists.txt):
#   bin/hydrosoft
#   lib/libhydrosoft_core.a, lib/libhydrosoft_solvers.a
#   include/hydrosoft/{common,deck,mesh,...,solvers}/*.hpp  (included as "deck/deck.hpp")
#   share/hydrosoft/input/*.yaml, share/hydrosoft/meshes/*   (the decks, runnable from there)
#   lib/cmake/hydrosoft/  find_package(hydrosoft): hydrosoft::core, hydrosoft::solvers,
#                         hydrosoft::fluidweight, hydrosoft::hydrosoft (the executable)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The installed executable keeps the run path of libraries outside the system's folders (a
# PETSc of its own prefix); the build tree's one is left as it is.
set_target_properties(hydrosoft PROPERTIES INSTALL_RPATH_USE_LINK_PATH ON)
set_target_properties(hydrosoft_core PROPERTIES EXPORT_NAME core)
set_target_properties(hydrosoft_solvers PROPERTIES EXPORT_NAME solvers)
install(TARGETS hydrosoft_core hydrosoft_solvers hydrosoft EXPORT hydrosoftTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hydrosoft
        FILES_MATCHING PATTERN "*.hpp")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/solvers/
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/hydrosoft/solvers FILES_MATCHING PATTERN "*.hpp")

# The decks name their meshes as ../meshes/..., so both folders keep their names side by side.
set(HYDROSOFT_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/hydrosoft)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/input ${PROJECT_SOURCE_DIR}/meshes
        DESTINATION ${HYDROSOFT_INSTALL_DATADIR})
# The Python control package and its example (PYTHONPATH=PREFIX/share/hydrosoft/python).
install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/hydrosoft_control ${PROJECT_SOURCE_DIR}/python/examples
        DESTINATION ${HYDROSOFT_INSTALL_DATADIR}/python PATTERN "__pycache__" EXCLUDE)

set(HYDROSOFT_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/hydrosoft)
install(EXPORT hydrosoftTargets NAMESPACE hydrosoft:: DESTINATION ${HYDROSOFT_INSTALL_CMAKEDIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hydrosoftConfig.cmake.in
  ${PROJECT_BINARY_DIR}/hydrosoftConfig.cmake INSTALL_DESTINATION ${HYDROSOFT_INSTALL_CMAKEDIR}
  PATH_VARS HYDROSOFT_INSTALL_DATADIR)
# 0.x: a minor version may change the library's interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hydrosoftConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/hydrosoftConfig.cmake
              ${PROJECT_BINARY_DIR}/hydrosoftConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/hydrosoftLibraries.cmake
        DESTINATION ${HYDROSOFT_INSTALL_CMAKEDIR})
