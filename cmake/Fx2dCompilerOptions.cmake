# Project-wide compiler settings. Warnings are errors on GCC and Clang; every flag that is not
# universal is probed rather than assumed.
include(CheckCXXCompilerFlag)

set(CMAKE_CXX_STANDARD 20)
set(CMAKE_CXX_STANDARD_REQUIRED ON)
set(CMAKE_CXX_EXTENSIONS OFF)
set(CMAKE_POSITION_INDEPENDENT_CODE ON)

if(FX2D_LTO)
  include(CheckIPOSupported)
  check_ipo_supported(RESULT fx2d_lto_supported OUTPUT fx2d_lto_output LANGUAGES CXX)
  if(NOT fx2d_lto_supported)
    message(FATAL_ERROR "FX2D_LTO: this compiler cannot optimise at link time: ${fx2d_lto_output}")
  endif()
  set(CMAKE_INTERPROCEDURAL_OPTIMIZATION ON)
endif()

add_library(fx2d_warnings INTERFACE)
target_compile_options(fx2d_warnings INTERFACE
  $<$<CXX_COMPILER_ID:GNU,Clang>:-Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Werror>)
# With link-time optimisation the compiler warns again while it optimises at the link.
if(FX2D_LTO)
  target_link_options(fx2d_warnings INTERFACE $<$<CXX_COMPILER_ID:GNU,Clang>:-Werror>)
endif()

if(FX2D_SANITIZE AND FX2D_TSAN)
  message(FATAL_ERROR "FX2D_SANITIZE and FX2D_TSAN exclude each other (ThreadSanitizer cannot run with ASan)")
endif()
if(FX2D_TSAN)
  set(fx2d_sanitize_flags -fsanitize=thread -fno-omit-frame-pointer)
  add_compile_options(${fx2d_sanitize_flags})
  add_link_options(${fx2d_sanitize_flags})
endif()
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
