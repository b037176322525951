// A library that presents itself as an fx2d-bench plugin of the next ABI version, with nothing
// behind it: plugin_test checks that the loader refuses it after reading abi_version alone.
#include "plugin/fx2d_plugin_abi.h"

extern "C" __attribute__((visibility("default"))) const Fx2dBenchPlugin* fx2d_bench_plugin_v1(void) {
  static const Fx2dBenchPlugin table = [] {
    Fx2dBenchPlugin next_version{};
    next_version.abi_version = FX2D_BENCH_PLUGIN_ABI_VERSION + 1;
    return next_version;
  }();
  return &table;
}
