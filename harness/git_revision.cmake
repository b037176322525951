# Writes OUTPUT, a header defining FX2D_BENCH_GIT_REVISION: the git revision of SOURCE_DIR as it is
# being built, `git rev-parse --short HEAD`, with "-dirty" when tracked files differ from HEAD (or
# git cannot tell that they do not), or "unknown" outside a git checkout or without git, which never
# fails the build. The build runs it every time (harness/CMakeLists.txt); the header is rewritten
# only when its text changes, so an unchanged revision recompiles nothing.
#   cmake -DSOURCE_DIR=<tree> -DOUTPUT=<header> -P git_revision.cmake
cmake_minimum_required(VERSION 3.25)
set(revision unknown)
execute_process(COMMAND git rev-parse --short HEAD WORKING_DIRECTORY ${SOURCE_DIR}
  OUTPUT_VARIABLE head OUTPUT_STRIP_TRAILING_WHITESPACE ERROR_QUIET RESULT_VARIABLE head_result)
if(head_result EQUAL 0 AND NOT head STREQUAL "")
  set(revision ${head})
  execute_process(COMMAND git diff --quiet HEAD -- WORKING_DIRECTORY ${SOURCE_DIR}
    OUTPUT_QUIET ERROR_QUIET RESULT_VARIABLE diff_result)
  if(NOT diff_result EQUAL 0)
    string(APPEND revision -dirty)
  endif()
endif()
file(CONFIGURE OUTPUT ${OUTPUT} @ONLY CONTENT [[
// Made by harness/git_revision.cmake on every build.
#define FX2D_BENCH_GIT_REVISION "@revision@"
]])
