# Writes granboltz/core/version.hpp with the current git commit; run at every build (the file is
# rewritten only when its content changes, so nothing recompiles needlessly).
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE GRANBOLTZ_GIT_SHA OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
execute_process(COMMAND git status --porcelain --untracked-files=no WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE _dirty OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET)
if(NOT GRANBOLTZ_GIT_SHA)
  set(GRANBOLTZ_GIT_SHA "unknown")
elseif(_dirty)
  set(GRANBOLTZ_GIT_SHA "${GRANBOLTZ_GIT_SHA}-dirty")
endif()
configure_file(${SOURCE_DIR}/src/granboltz/core/version.hpp.in ${OUTPUT} @ONLY)
