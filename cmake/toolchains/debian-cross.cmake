# What every cross toolchain here shares, included after it sets fx2d_target_root (where Debian
# installs the target's libraries): libraries and packages come from the target root only, never
# the host's; programs (python, git) are the host's.
list(APPEND CMAKE_FIND_ROOT_PATH ${fx2d_target_root})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)

# nlohmann-json is header-only and the same on every architecture, so the host's
# package serves the target. Its CMake package is found where Debian puts it, outside the
# target root. nlohmann-json's target adds the host's /usr/include to the include path; searching
# it with -idirafter (after every directory of the target's own) keeps the host's C library
# headers from ever shadowing the target's, and makes CMake's compiler probe count /usr/include as
# implicit, so it drops nlohmann-json's -isystem /usr/include from the command lines.
set(nlohmann_json_DIR /usr/share/cmake/nlohmann_json CACHE PATH "nlohmann_jsonConfig.cmake (header-only, from the host)")
set(CMAKE_C_FLAGS_INIT "-idirafter /usr/include")
set(CMAKE_CXX_FLAGS_INIT "-idirafter /usr/include")
