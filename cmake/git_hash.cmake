# Run at every build (target lem_git_hash): writes OUTPUT, a header defining
# LEM_GIT_HASH as the source tree's commit (with "-dirty" for uncommitted
# changes to tracked files), and touches it only when the text changes, so
# that a new commit recompiles src/base/provenance.cpp alone and an
# unchanged tree recompiles nothing.
#   cmake -DSOURCE_DIR=<tree> -DOUTPUT=<header> -P git_hash.cmake
set(hash unknown)
execute_process(COMMAND git rev-parse --short=12 HEAD WORKING_DIRECTORY ${SOURCE_DIR}
                OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE
                RESULT_VARIABLE failed ERROR_QUIET)
if(NOT failed AND head)
  set(hash ${head})
  execute_process(COMMAND git status --porcelain --untracked-files=no
                  WORKING_DIRECTORY ${SOURCE_DIR} OUTPUT_VARIABLE changes ERROR_QUIET)
  if(changes)
    set(hash ${hash}-dirty)
  endif()
endif()
set(text "// Generated at build time by cmake/git_hash.cmake.\n#define LEM_GIT_HASH \"${hash}\"\n")
set(old "")
if(EXISTS ${OUTPUT})
  file(READ ${OUTPUT} old)
endif()
if(NOT old STREQUAL text)
  file(WRITE ${OUTPUT} "${text}")
endif()
