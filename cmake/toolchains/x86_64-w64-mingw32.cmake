# Cross-compiles for 64-bit Windows with Debian's MinGW-w64 GCC (posix threads:
# g++-mingw-w64-x86-64-posix) and runs the results under Wine, so ctest on Linux runs the .exe
# files. ci/cross-mingw uses it; by hand:
#   cmake -S . -B build/mingw --toolchain cmake/toolchains/x86_64-w64-mingw32.cmake
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(fx2d_target_triple x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${fx2d_target_triple}-gcc-posix)
set(CMAKE_CXX_COMPILER ${fx2d_target_triple}-g++-posix)
set(CMAKE_RC_COMPILER ${fx2d_target_triple}-windres)

# Each build directory has a Wine prefix of its own, made on first use (wine-run).
set(CMAKE_CROSSCOMPILING_EMULATOR ${CMAKE_CURRENT_LIST_DIR}/wine-run ${CMAKE_BINARY_DIR}/wineprefix)

# libstdc++, libgcc and winpthread linked into every .exe, so Wine needs no MinGW DLL beside it.
set(CMAKE_EXE_LINKER_FLAGS_INIT -static)

# The MinGW-w64 runtime and Windows API libraries.
set(fx2d_target_root /usr/${fx2d_target_triple})
include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
