# Writes OUT with the project's commit for result provenance: `git describe --always
# --dirty=+dirty --abbrev=12` in SRC, or "unknown" outside a git checkout. Run at every
# build (harness/CMakeLists.txt); the file is rewritten only when the text changes, so a
# clean rebuild does not recompile anything.
execute_process(COMMAND git describe --always --dirty=+dirty --abbrev=12
  WORKING_DIRECTORY "${SRC}"
  OUTPUT_VARIABLE commit OUTPUT_STRIP_TRAILING_WHITESPACE
  ERROR_QUIET RESULT_VARIABLE rc)
if(NOT rc EQUAL 0 OR commit STREQUAL "")
  set(commit "unknown")
endif()
set(text "#pragma once\n#define REFRASTER_GIT_COMMIT \"${commit}\"\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
else()
  set(old "")
endif()
if(NOT old STREQUAL text)
  file(WRITE "${OUT}" "${text}")
endif()
