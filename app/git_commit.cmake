# Writes OUTPUT (a header defining kGitCommit) from `git describe` of SOURCE_DIR, at every
# build, touching it only when the commit changes (so nothing rebuilds for nothing).
execute_process(COMMAND git -C "${SOURCE_DIR}" describe --always --dirty --abbrev=12
                OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET
                RESULT_VARIABLE failed)
if(failed OR commit STREQUAL "")
  set(commit "unknown: not a git checkout")
endif()
file(WRITE "${OUTPUT}.new" "#pragma once\ninline constexpr const char* kGitCommit = \"${commit}\";\n")
execute_process(COMMAND ${CMAKE_COMMAND} -E copy_if_different "${OUTPUT}.new" "${OUTPUT}")
file(REMOVE "${OUTPUT}.new")
