# fx2d_bench_add_engine_plugin(NAME SOURCES file... [LIBRARIES target-or-lib...])
#
# Adds MODULE library NAME: an fx2d-bench engine plugin (fx2d_plugin_abi.h) built from SOURCES and
# linked with LIBRARIES (the engine), exporting exactly one symbol, fx2d_bench_plugin_v1, so that
# two builds of one engine load side by side with dlopen(RTLD_LOCAL) and never share a symbol.
# The same file serves this source tree (Fx2D's and Chipmunk2D's plugins) and the installed SDK
# (find_package(Fx2dBench), Fx2dBenchConfig.cmake), which differ only in where the header and the
# version script lie: FX2D_BENCH_PLUGIN_INCLUDE_DIR and FX2D_BENCH_PLUGIN_VERSION_SCRIPT, set
# beside this file unless set before including it.
if(NOT DEFINED FX2D_BENCH_PLUGIN_INCLUDE_DIR)
  set(FX2D_BENCH_PLUGIN_INCLUDE_DIR ${CMAKE_CURRENT_LIST_DIR})
endif()
if(NOT DEFINED FX2D_BENCH_PLUGIN_VERSION_SCRIPT)
  set(FX2D_BENCH_PLUGIN_VERSION_SCRIPT ${CMAKE_CURRENT_LIST_DIR}/fx2d_plugin.map)
endif()

function(fx2d_bench_add_engine_plugin name)
  cmake_parse_arguments(PARSE_ARGV 1 plugin "" "" "SOURCES;LIBRARIES")
  if(NOT plugin_SOURCES)
    message(FATAL_ERROR "fx2d_bench_add_engine_plugin(${name}): expected SOURCES with the adapter's files")
  endif()
  add_library(${name} MODULE ${plugin_SOURCES})
  target_include_directories(${name} PRIVATE ${FX2D_BENCH_PLUGIN_INCLUDE_DIR})
  target_link_libraries(${name} PRIVATE ${plugin_LIBRARIES})
  target_compile_features(${name} PRIVATE cxx_std_20)
  set_target_properties(${name} PROPERTIES
    C_VISIBILITY_PRESET hidden
    CXX_VISIBILITY_PRESET hidden
    VISIBILITY_INLINES_HIDDEN ON
    POSITION_INDEPENDENT_CODE ON)
  # Static libraries inside export nothing, whatever visibility their objects were compiled with;
  # the version script also hides what std:: headers force to default visibility (fx2d_plugin.map).
  if(NOT WIN32)
    target_link_options(${name} PRIVATE -Wl,--exclude-libs,ALL -Wl,--version-script=${FX2D_BENCH_PLUGIN_VERSION_SCRIPT})
    set_property(TARGET ${name} APPEND PROPERTY LINK_DEPENDS ${FX2D_BENCH_PLUGIN_VERSION_SCRIPT})
  endif()
endfunction()
