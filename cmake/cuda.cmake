# The optional CUDA backend of the rasterizer: liblidarscout_cuda_raster.so, a plugin opened
# with dlopen by src/render/cuda_plugin.cpp (so no program links the CUDA runtime). Built when
# nvcc is found (LIDARSCOUT_CUDA=AUTO, the default), required with ON, skipped with OFF; when
# it cannot be built the project stays CPU-only and says so.
set(LIDARSCOUT_CUDA "AUTO" CACHE STRING "Build the CUDA rasterizer plugin: AUTO (when nvcc is found), ON or OFF")
set_property(CACHE LIDARSCOUT_CUDA PROPERTY STRINGS AUTO ON OFF)

# Where the loader looks for the plugin from a build tree (next to the programs).
set_property(SOURCE src/render/cuda_plugin.cpp APPEND PROPERTY COMPILE_DEFINITIONS
             "LIDARSCOUT_BUILD_DIR=\"${CMAKE_BINARY_DIR}\"")

set(LIDARSCOUT_CUDA_BUILT OFF)
if(NOT LIDARSCOUT_CUDA STREQUAL "OFF")
  # The usual toolkit place, when nvcc is not on the PATH.
  if(NOT CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX} AND EXISTS /usr/local/cuda/bin/nvcc)
    set(ENV{CUDACXX} /usr/local/cuda/bin/nvcc)
  endif()
  include(CheckLanguage)
  check_language(CUDA)
  if(CMAKE_CUDA_COMPILER)
    if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
      # A100 and H100/H200 machine code, plus PTX of sm_90 for newer GPUs.
      set(CMAKE_CUDA_ARCHITECTURES "80-real;90")
    endif()
    enable_language(CUDA)
    set(LIDARSCOUT_CUDA_BUILT ON)
  elseif(LIDARSCOUT_CUDA STREQUAL "ON")
    message(FATAL_ERROR "LIDARSCOUT_CUDA=ON but no working CUDA compiler (nvcc) was found")
  endif()
endif()

if(LIDARSCOUT_CUDA_BUILT)
  message(STATUS
          "lidarscout: building the CUDA rasterizer plugin (liblidarscout_cuda_raster.so) with ${CMAKE_CUDA_COMPILER}")
  add_library(lidarscout_cuda_raster MODULE src/render/cuda/raster_plugin.cu src/render/cuda/raster_kernels.cu)
  target_include_directories(lidarscout_cuda_raster PRIVATE ${CMAKE_SOURCE_DIR}/src)
  # The directory's warning and sanitizer flags are for the host compiler only.
  set_property(TARGET lidarscout_cuda_raster PROPERTY COMPILE_OPTIONS "")
  set_property(TARGET lidarscout_cuda_raster PROPERTY LINK_OPTIONS "")
  # --fmad=false: float expressions round as on the CPU, so both backends draw the same image.
  target_compile_options(lidarscout_cuda_raster PRIVATE --fmad=false -Xcompiler=-Wall,-fvisibility=hidden)
  set_target_properties(lidarscout_cuda_raster PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}
    CUDA_STANDARD 17
    CUDA_RUNTIME_LIBRARY Static     # needs only the driver (libcuda) at run time
    CUDA_VISIBILITY_PRESET hidden)
  add_dependencies(lidarscout lidarscout_cuda_raster)
  if(TARGET lidarscout_tests)
    add_dependencies(lidarscout_tests lidarscout_cuda_raster)
  endif()
else()
  message(STATUS "lidarscout: no CUDA compiler (or LIDARSCOUT_CUDA=OFF): CPU rasterizer only")
endif()
