# ctest's install_package: `cmake --install` of this build into a temporary prefix, then the
# installed pieces used as a user would use them: hydrosoft --version run from the prefix, and
# the project in consumer/ configured with find_package(fluidweight) and find_package(hydrosoft),
# built and run (its checks: consumer/main.cpp). The temporary folder is removed at the end,
# failed or not. Run as
#   cmake -DBUILD_DIR=... -DCONSUMER_DIR=... -DGENERATOR=... -DC_COMPILER=... -DCXX_COMPILER=...
#         [-DLAUNCHER=ccache] [-DMPIEXEC="mpiexec;--oversubscribe"] -P install_test.cmake
set(base "$ENV{TMPDIR}")
if(NOT base)
  set(base /tmp)
endif()
string(RANDOM LENGTH 10 suffix)
set(tmp "${base}/hydrosoft_install_test_${suffix}")
set(prefix "${tmp}/prefix")
file(MAKE_DIRECTORY "${tmp}")

function(fail what)
  file(REMOVE_RECURSE "${tmp}")
  message(FATAL_ERROR "install test: ${what}")
endfunction()

# Runs a command; fails with its output unless it exits 0. Its output is left in `output`.
function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out
                  ERROR_VARIABLE out)
  message(STATUS "install test: ${name}")
  if(NOT status EQUAL 0)
    fail("${name} failed (${status}):\n${out}")
  endif()
  set(output "${out}" PARENT_SCOPE)
endfunction()

step("install into ${prefix}" ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(file bin/hydrosoft bin/fluidweight include/fluidweight/fluidweight.hpp
             include/hydrosoft/deck/deck.hpp include/hydrosoft/solvers/problem.hpp
             share/hydrosoft/input/finger_from_step.yaml share/hydrosoft/meshes/finger_cad.step
             lib/cmake/hydrosoft/hydrosoftConfigVersion.cmake
             lib/cmake/fluidweight/fluidweightConfigVersion.cmake)
  if(NOT EXISTS "${prefix}/${file}")
    fail("${file} is not installed")
  endif()
endforeach()

step("hydrosoft --version from the prefix" "${prefix}/bin/hydrosoft" --version)
if(NOT output MATCHES "hydrosoft [0-9.]+ \\(commit .*PETSc 3")
  fail("unexpected hydrosoft --version:\n${output}")
endif()

step("the Python control package from the prefix" /usr/bin/python3 -c
     "import sys\nsys.path.insert(0, '${prefix}/share/hydrosoft/python')\nimport hydrosoft_control\nprint(hydrosoft_control.find_executable())")
if(NOT output MATCHES "${prefix}/bin/hydrosoft")
  fail("the installed Python package does not find the installed hydrosoft:\n${output}")
endif()

set(configure ${CMAKE_COMMAND} -S "${CONSUMER_DIR}" -B "${tmp}/build" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${prefix}"
    "-DCMAKE_C_COMPILER=${C_COMPILER}" "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
if(LAUNCHER)
  list(APPEND configure "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
endif()
step("configure the consumer" ${configure})
step("build the consumer" ${CMAKE_COMMAND} --build "${tmp}/build" -j 2)

step("run weight_only" "${tmp}/build/weight_only")
message("${output}")
step("run consumer" "${tmp}/build/consumer")
message("${output}")
if(NOT output MATCHES "mesh .*/share/hydrosoft/meshes/finger_cad.geo"
   OR NOT output MATCHES "consumer: all checks passed")
  fail("unexpected consumer output:\n${output}")
endif()

# The controller from another program, on 1 rank and, with MPIEXEC, on 2.
step("run control" "${tmp}/build/control")
message("${output}")
if(NOT output MATCHES "control: all checks passed")
  fail("unexpected control output:\n${output}")
endif()
if(MPIEXEC)
  step("run control on 2 ranks" ${MPIEXEC} -np 2 "${tmp}/build/control")
  message("${output}")
  if(NOT output MATCHES "control: all checks passed")
    fail("unexpected control output on 2 ranks:\n${output}")
  endif()
endif()

file(REMOVE_RECURSE "${tmp}")
