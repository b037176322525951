# Project-wide compiler settings. Warnings are errors on GCC and Clang; every flag that is not
# universal is probed rather than assumed.
include(CheckCXXCompilerFlag)

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)

add_library(fx2d_warnings INTERFACE)
target_compile_options(fx2d_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Werror>)

if(FX2D_SANITIZE)
  set(fx2d_sanitize_flags -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${fx2d_sanitize_flags})
  add_link_options(${fx2d_sanitize_flags})
  # Under ASan instrumentation GCC 12 reports -Wmaybe-uninitialized inside libstdc++'s <regex>
  # (std::function moves in regex_automaton.h); the Release build keeps the warning as an error.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(fx2d_warnings INTERFACE -Wno-maybe-uninitialized)
  endif()
endif()
