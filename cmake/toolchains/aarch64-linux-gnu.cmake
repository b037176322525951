# Cross-compiles for 64-bit Arm Linux with Debian's toolchain (g++-aarch64-linux-gnu) and runs the
# results under qemu-user, so ctest on an x86-64 machine runs the aarch64 binaries. ci/cross-aarch64
# uses it; by hand:
#   cmake -S . -B build/aarch64 --toolchain cmake/toolchains/aarch64-linux-gnu.cmake
set(CMAKE_SYSTEM_NAME Linux)
set(CMAKE_SYSTEM_PROCESSOR aarch64)
set(fx2d_target_triple aarch64-linux-gnu)
set(CMAKE_C_COMPILER ${fx2d_target_triple}-gcc)
set(CMAKE_CXX_COMPILER ${fx2d_target_triple}-g++)

# The target's C library and libstdc++ live under this root; qemu loads them from there too.
set(fx2d_target_root /usr/${fx2d_target_triple})
set(CMAKE_CROSSCOMPILING_EMULATOR qemu-aarch64 -L ${fx2d_target_root})

include(${CMAKE_CURRENT_LIST_DIR}/debian-cross.cmake)
