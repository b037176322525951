# The shared body of ci/cross-aarch64 and ci/cross-mingw, which source this file and call
#   cross_build_and_test NAME TOOLCHAIN NOT_RUNNABLE QUICK_SKIP ARGUMENT [CMAKE_ARGUMENTS...]
# It builds GoogleTest for the target from Debian's sources (/usr/src/googletest) inside the build
# directory, which keeps the host's dpkg free of a foreign architecture; configures Fx2D with
# TOOLCHAIN, FX2D_HARNESS_PORTABLE_ONLY and CMAKE_ARGUMENTS; builds it and runs its tests under the
# toolchain's emulator, all but those matching NOT_RUNNABLE (a ctest regular expression).
# ARGUMENT is the calling script's own: empty for every engine test and every portable harness
# test, --quick for the engine tests and the golden test only (what .ci/run can afford), less
# those matching QUICK_SKIP (a ctest regular expression, or empty).
# Environment: FX2D_CROSS_BUILD_DIR (default build/NAME), FX2D_JOBS (default nproc);
# CMake reads CMAKE_CXX_COMPILER_LAUNCHER (e.g. ccache) from the environment itself.
cross_build_and_test() {
  local name=$1 toolchain=$2 not_runnable=$3 quick_skip=$4 argument=$5
  shift 5
  local quick=false
  case $argument in
    "") ;;
    --quick) quick=true ;;
    *)
      echo "ci/cross-$name: unknown argument '$argument'; expected nothing or --quick" >&2
      exit 2
      ;;
  esac
  local root build jobs
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  build=${FX2D_CROSS_BUILD_DIR:-$root/build/$name}
  jobs=${FX2D_JOBS:-$(nproc)}

  "$root/ci/install-deps"

  local gtest_prefix=$build/googletest
  if [[ ! -f $gtest_prefix/lib/cmake/GTest/GTestConfig.cmake ]]; then
    echo "== $name: GoogleTest from /usr/src/googletest" >&2
    cmake -S /usr/src/googletest -B "$build/googletest-build" --toolchain "$toolchain" -DCMAKE_BUILD_TYPE=Release \
      -DBUILD_GMOCK=OFF -DINSTALL_GTEST=ON -DCMAKE_INSTALL_PREFIX="$gtest_prefix" >/dev/null
    cmake --build "$build/googletest-build" -j "$jobs"
    cmake --install "$build/googletest-build" >/dev/null
  fi

  echo "== $name: Fx2D$($quick && echo ' (quick)')" >&2
  # Makefiles, so that --quick can build one directory's targets (cmake --build on a subdirectory).
  cmake -S "$root" -B "$build" -G "Unix Makefiles" --toolchain "$toolchain" -DCMAKE_BUILD_TYPE=Release \
    -DFX2D_HARNESS_PORTABLE_ONLY=ON -DGTest_DIR="$gtest_prefix/lib/cmake/GTest" "$@" >/dev/null

  # A test that fails under the emulator runs once more, and fails the stage only if it fails
  # again: under Wine a test has failed at its start with "wine client error:0: recvmsg:
  # Connection reset by peer" (a fresh clone of cbbf882), the emulator's client losing its server,
  # not the test. Both runs' output stays in the log, and every test here also runs natively, once,
  # in the Linux stages.
  local retry=(--repeat until-pass:2)
  if $quick; then
    cmake --build "$build/fx2d" -j "$jobs"
    cmake --build "$build" -j "$jobs" --target fx2d_golden_test
    # Only the tests of what was built: the others are registered as <target>_NOT_BUILT.
    ctest --test-dir "$build" -j "$jobs" --output-on-failure --timeout 600 "${retry[@]}" \
      -E "$not_runnable|_NOT_BUILT${quick_skip:+|$quick_skip}"
  else
    cmake --build "$build" -j "$jobs"
    ctest --test-dir "$build" -j "$jobs" --output-on-failure --timeout 600 "${retry[@]}" -E "$not_runnable"
  fi
}
