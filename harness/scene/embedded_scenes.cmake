# Compiles the canonical scene files into fx2d_bench_scene as raw string literals, so scenes/*.json
# stay the one source of truth: editing one re-runs this step (CMAKE_CONFIGURE_DEPENDS) and the
# binary follows. Produces ${CMAKE_CURRENT_BINARY_DIR}/embedded_scenes.cpp.
set(fx2d_canonical_scenes pile stacks settling_boxes)
set(fx2d_scene_delimiter "fx2d_scene")

set(FX2D_EMBEDDED_SCENE_ENTRIES "")
foreach(scene IN LISTS fx2d_canonical_scenes)
  set(scene_file "${PROJECT_SOURCE_DIR}/scenes/${scene}.json")
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${scene_file}")
  file(READ "${scene_file}" scene_text)
  string(FIND "${scene_text}" ")${fx2d_scene_delimiter}\"" delimiter_at)
  if(NOT delimiter_at EQUAL -1)
    message(FATAL_ERROR "${scene_file} contains the raw-string delimiter )${fx2d_scene_delimiter}\"")
  endif()
  string(APPEND FX2D_EMBEDDED_SCENE_ENTRIES
    "    {\"${scene}\", R\"${fx2d_scene_delimiter}(${scene_text})${fx2d_scene_delimiter}\"},\n")
endforeach()

configure_file("${CMAKE_CURRENT_SOURCE_DIR}/embedded_scenes.cpp.in"
               "${CMAKE_CURRENT_BINARY_DIR}/embedded_scenes.cpp" @ONLY)
