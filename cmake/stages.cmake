# One static library per stage (one folder under src/), with its dependencies declared.
#
#   lidarscout_stage(NAME [DEPS stage...] [EXCLUDE regex...] [LINK target...])
#
# builds lidarscout_NAME from src/NAME/**/*.cpp (minus EXCLUDE) and links the DEPS stages.
# The layers are enforced by the build: a stage compiles against an include view that holds
# only itself and the stages it depends on (directly or through them), as symbolic links
# under build/stage_views/NAME/. So `#include "viewer/..."` in las/ fails to compile: viewer
# is not in las's view. A stage may only depend on stages declared before it, which keeps the
# order (core, net, io, las, geo, laz, dataset, recon, nn, pipelines, raster, render, viewer, synth,
# cli).

set_property(GLOBAL PROPERTY LIDARSCOUT_STAGES "")  # stages declared so far, in layer order

function(lidarscout_stage name)
  cmake_parse_arguments(S "" "" "DEPS;EXCLUDE;LINK" ${ARGN})
  # the view: this stage and the transitive closure of its dependencies
  get_property(declared GLOBAL PROPERTY LIDARSCOUT_STAGES)
  set(view_stages ${name})
  foreach(dep IN LISTS S_DEPS)
    if(NOT dep IN_LIST declared)
      message(FATAL_ERROR "stage ${name} depends on ${dep}, which is not a stage declared before it")
    endif()
    get_property(dep_view GLOBAL PROPERTY LIDARSCOUT_VIEW_${dep})
    list(APPEND view_stages ${dep_view})
  endforeach()
  list(REMOVE_DUPLICATES view_stages)
  set_property(GLOBAL PROPERTY LIDARSCOUT_VIEW_${name} ${view_stages})

  lidarscout_stage_view(${name} view_dir)
  file(REMOVE_RECURSE ${view_dir})
  file(MAKE_DIRECTORY ${view_dir})
  foreach(s IN LISTS view_stages)
    file(CREATE_LINK ${CMAKE_SOURCE_DIR}/src/${s} ${view_dir}/${s} SYMBOLIC)
  endforeach()

  file(GLOB_RECURSE sources CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/${name}/*.cpp)
  foreach(pattern IN LISTS S_EXCLUDE)
    list(FILTER sources EXCLUDE REGEX "${pattern}")
  endforeach()
  add_library(lidarscout_${name} STATIC ${sources})
  target_include_directories(lidarscout_${name} PRIVATE ${view_dir})
  foreach(dep IN LISTS S_DEPS)
    target_link_libraries(lidarscout_${name} PUBLIC lidarscout_${dep})
  endforeach()
  if(S_LINK)
    target_link_libraries(lidarscout_${name} ${S_LINK})
  endif()
  set_property(GLOBAL APPEND PROPERTY LIDARSCOUT_STAGES ${name})
endfunction()

# The include view of a stage (for a target compiled against it, e.g. an object library).
function(lidarscout_stage_view name out_var)
  set(${out_var} ${CMAKE_BINARY_DIR}/stage_views/${name} PARENT_SCOPE)
endfunction()
