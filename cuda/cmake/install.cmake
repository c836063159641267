# What `cmake --install` puts under the prefix P, from a build of cuda/ alone or of hydrosoft:
#   bin/fluidweight, lib/libhydrosoft_fluidweight.a, include/fluidweight/*.hpp
#   lib/cmake/fluidweight/  find_package(fluidweight): fluidweight::fluidweight (the library),
#                           fluidweight::cli (the command line)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set_target_properties(hydrosoft_fluidweight PROPERTIES EXPORT_NAME fluidweight)
set_target_properties(fluidweight PROPERTIES EXPORT_NAME cli)
install(TARGETS hydrosoft_fluidweight fluidweight EXPORT fluidweightTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/../include/fluidweight
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})

set(FLUIDWEIGHT_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/fluidweight)
install(EXPORT fluidweightTargets NAMESPACE fluidweight:: DESTINATION ${FLUIDWEIGHT_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/fluidweightConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/fluidweightConfig.cmake
  INSTALL_DESTINATION ${FLUIDWEIGHT_INSTALL_CMAKEDIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/fluidweightConfigVersion.cmake
  VERSION ${FLUIDWEIGHT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/fluidweightConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/fluidweightConfigVersion.cmake
        DESTINATION ${FLUIDWEIGHT_INSTALL_CMAKEDIR})
