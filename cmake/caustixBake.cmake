# caustix_bake(<target> SCENE <scene.json> OUTPUT <file.cxb>
#              [PRESET fast|balanced|accurate] [OPTIONS <caustix-bake arg>...])
#
# Adds <target>, built by default (ALL), that bakes SCENE into OUTPUT with
# caustix-bake. The baker writes a depfile naming scene.json and every mesh
# it read, so Ninja and Makefiles re-bake exactly when one of them (or the
# baker, or these arguments) changes, and not otherwise. SCENE is relative
# to the current source directory, OUTPUT to the current binary directory.
# The target's CAUSTIX_BAKE_OUTPUT property holds OUTPUT's absolute path.
# The baker is deterministic (same inputs: byte-identical file), so bakes run
# in parallel and cache like any other build step.
function(caustix_bake target)
  cmake_parse_arguments(PARSE_ARGV 1 CXB "" "SCENE;OUTPUT;PRESET" "OPTIONS")
  if(CXB_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "caustix_bake(${target}): unknown arguments: ${CXB_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT CXB_SCENE OR NOT CXB_OUTPUT)
    message(FATAL_ERROR "caustix_bake(${target}): SCENE <scene.json> and OUTPUT <file.cxb> are required")
  endif()
  if(NOT TARGET caustix::caustix-bake)
    message(FATAL_ERROR "caustix_bake(${target}): the imported caustix::caustix-bake is missing (find_package(caustix) first)")
  endif()
  get_filename_component(scene "${CXB_SCENE}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_SOURCE_DIR}")
  get_filename_component(output "${CXB_OUTPUT}" ABSOLUTE BASE_DIR "${CMAKE_CURRENT_BINARY_DIR}")
  if(NOT EXISTS "${scene}")
    message(FATAL_ERROR "caustix_bake(${target}): SCENE ${scene} does not exist")
  endif()
  set(args)
  if(CXB_PRESET)
    list(APPEND args --preset "${CXB_PRESET}")
  endif()
  # A depfile per target, beside its output.
  set(depfile "${CMAKE_CURRENT_BINARY_DIR}/CMakeFiles/${target}.cxb.d")
  cmake_policy(PUSH)
  cmake_policy(SET CMP0116 NEW)  # depfile paths handled alike by Ninja and Makefiles
  add_custom_command(OUTPUT "${output}"
    COMMAND caustix::caustix-bake "${scene}" -o "${output}" --depfile "${depfile}" --quiet ${args} ${CXB_OPTIONS}
    DEPENDS "${scene}" caustix::caustix-bake
    DEPFILE "${depfile}"
    COMMENT "caustix-bake ${CXB_SCENE} -> ${CXB_OUTPUT}"
    VERBATIM)
  cmake_policy(POP)
  add_custom_target(${target} ALL DEPENDS "${output}")
  set_target_properties(${target} PROPERTIES CAUSTIX_BAKE_OUTPUT "${output}")
endfunction()
