# One static library per stage (one folder under src/), with its dependencies declared.
#
#   lidarscout_stage(NAME [DEPS stage...] [EXCLUDE regex...] [FACADE entry...] [LINK target...])
#
# builds lidarscout_NAME from src/NAME/**/*.cpp (minus EXCLUDE) and links the DEPS stages.
# FACADE names the entries of src/NAME (files or folders) that later stages see, its public face: in
# their views src/NAME is a folder of links to those entries only, so including any other header
# of the stage fails to compile there (the stage itself, tests and benchmarks see all of it).
# Without FACADE every entry is seen.
# The layers are enforced by the build: a stage compiles against an include view that holds
# only itself and the stages it depends on (directly or through them), as symbolic links
# under build/stage_views/NAME/. So `#include "viewer/..."` in las/ fails to compile: viewer
# is not in las's view. A stage may only depend on stages declared before it, which keeps the
# order (core, net, io, las, geo, laz, dataset, recon, nn, pipelines, raster, render, viewer, synth,
# cli). The view holds the dependencies' dependencies too (their headers include them), so a
# second check reads the stage's own files: every `#include "S/..."` of another stage S must name
# a stage declared in DEPS, else configuring fails naming both stages and the file, and a
# declared stage it includes nothing of fails too (lidarscout_check_includes; the suite's
# StageIncludes test shows both failing).

set_property(GLOBAL PROPERTY LIDARSCOUT_STAGES "")  # stages declared so far, in layer order

function(lidarscout_stage name)
  cmake_parse_arguments(S "" "" "DEPS;EXCLUDE;FACADE;LINK" ${ARGN})
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
  set_property(GLOBAL PROPERTY LIDARSCOUT_FACADE_${name} ${S_FACADE})
  foreach(s IN LISTS view_stages)
    get_property(public GLOBAL PROPERTY LIDARSCOUT_FACADE_${s})
    if(s STREQUAL name OR NOT public)
      file(CREATE_LINK ${CMAKE_SOURCE_DIR}/src/${s} ${view_dir}/${s} SYMBOLIC)
    else()
      lidarscout_public_view(${s} "${public}" ${view_dir}/${s})
    endif()
  endforeach()

  lidarscout_check_includes(${name} "${S_DEPS}" "${declared}")
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

# The public face of stage `s` in a later stage's view: a folder `dir` with a link to each of its
# `public` entries (an entry that does not exist is a mistake in the stage's declaration).
function(lidarscout_public_view s public dir)
  file(MAKE_DIRECTORY ${dir})
  foreach(entry IN LISTS public)
    if(NOT EXISTS ${CMAKE_SOURCE_DIR}/src/${s}/${entry})
      message(FATAL_ERROR "stage ${s} declares FACADE ${entry}, which is not in src/${s}")
    endif()
    file(CREATE_LINK ${CMAKE_SOURCE_DIR}/src/${s}/${entry} ${dir}/${entry} SYMBOLIC)
  endforeach()
endfunction()

# The include view of a stage (for a target compiled against it, e.g. an object library).
function(lidarscout_stage_view name out_var)
  set(${out_var} ${CMAKE_BINARY_DIR}/stage_views/${name} PARENT_SCOPE)
endfunction()

# Fails (FATAL_ERROR) when a file of stage `name` includes a header of a stage in `stages` that is
# neither `name` nor one of `deps`, naming the stage, the file and the stage it includes.
function(lidarscout_check_includes name deps stages)
  set(unused ${deps})
  file(GLOB_RECURSE own CONFIGURE_DEPENDS ${CMAKE_SOURCE_DIR}/src/${name}/*.cpp ${CMAKE_SOURCE_DIR}/src/${name}/*.hpp
       ${CMAKE_SOURCE_DIR}/src/${name}/*.h ${CMAKE_SOURCE_DIR}/src/${name}/*.cu)
  foreach(f IN LISTS own)
    file(STRINGS ${f} includes REGEX "^#include \"[a-z_]+/")
    foreach(line IN LISTS includes)
      string(REGEX MATCH "^#include \"([a-z_]+)/" matched "${line}")
      set(used ${CMAKE_MATCH_1})
      list(REMOVE_ITEM unused ${used})
      if(used IN_LIST stages AND NOT used STREQUAL name AND NOT used IN_LIST deps)
        file(RELATIVE_PATH where ${CMAKE_SOURCE_DIR} ${f})
        message(FATAL_ERROR "stage ${name} includes stage ${used} without declaring it (${where}: ${line}); "
                            "add ${used} to its DEPS or move the code")
      endif()
    endforeach()
  endforeach()
  if(unused)
    message(FATAL_ERROR "stage ${name} declares DEPS ${unused} but includes nothing of them; remove them")
  endif()
endfunction()
