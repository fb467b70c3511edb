# SPDX-License-Identifier: MIT
# vplrender_core: the example renderer's library (scene, loaders, outputs, options). Included from
# examples/CMakeLists.txt and from tests/renderer/CMakeLists.txt, whichever CMake reaches first
# (tests come first in the top-level list, and the tests also build with examples switched off).
include_guard(GLOBAL)

set(VPLRENDER_CORE_AVAILABLE OFF)
set(_vplrender_missing "")
find_package(tinyobjloader CONFIG QUIET)
if(NOT TARGET tinyobjloader::tinyobjloader)
  list(APPEND _vplrender_missing "tinyobjloader (libtinyobjloader-dev)")
endif()
find_package(OpenEXR 3 CONFIG QUIET)
if(NOT TARGET OpenEXR::OpenEXR)
  list(APPEND _vplrender_missing "OpenEXR 3 (libopenexr-dev)")
endif()
find_package(CLI11 2 CONFIG QUIET)
if(NOT TARGET CLI11::CLI11)
  list(APPEND _vplrender_missing "CLI11 (libcli11-dev)")
endif()
# Embree 3: exact visibility on the CPU backend and --method exact (render/cpu/ray_scene.hpp).
find_package(embree 3 CONFIG QUIET)
if(NOT TARGET embree)
  list(APPEND _vplrender_missing "Embree 3 (libembree-dev)")
endif()
find_package(nlohmann_json 3 CONFIG QUIET)
if(NOT TARGET nlohmann_json::nlohmann_json)
  list(APPEND _vplrender_missing "nlohmann_json (nlohmann-json3-dev)")
endif()
# Debian's libstb-dev ships the implementations compiled in libstb.so; headers live in .../stb/.
find_path(VPLRENDER_STB_INCLUDE_DIR stb_image.h PATH_SUFFIXES stb)
find_library(VPLRENDER_STB_LIBRARY stb)
if(NOT VPLRENDER_STB_INCLUDE_DIR OR NOT VPLRENDER_STB_LIBRARY)
  list(APPEND _vplrender_missing "stb_image (libstb-dev)")
endif()

if(_vplrender_missing)
  list(JOIN _vplrender_missing ", " _vplrender_missing_text)
  message(WARNING "vplrender (the example renderer) and its tests are skipped: missing ${_vplrender_missing_text}")
  return()
endif()

# The imported targets above are scoped to the directory that found them; vplrender_core is used
# from two directories, so promote them (and what they drag in) to global.
foreach(_t tinyobjloader::tinyobjloader OpenEXR::OpenEXR OpenEXR::Iex OpenEXR::IlmThread OpenEXR::OpenEXRCore
           OpenEXR::OpenEXRConfig OpenEXR::IexConfig OpenEXR::IlmThreadConfig OpenEXR::OpenEXRUtil
           Imath::Imath Imath::ImathConfig CLI11::CLI11 nlohmann_json::nlohmann_json embree)
  if(TARGET ${_t})
    get_target_property(_global ${_t} IMPORTED_GLOBAL)
    get_target_property(_imported ${_t} IMPORTED)
    if(_imported AND NOT _global)
      set_target_properties(${_t} PROPERTIES IMPORTED_GLOBAL TRUE)
    endif()
  endif()
endforeach()

set(_vr ${CMAKE_CURRENT_LIST_DIR}/src)
add_library(vplrender_core STATIC
  ${_vr}/app/lighting_check.cpp
  ${_vr}/cli/options.cpp
  ${_vr}/app/progress.cpp
  ${_vr}/app/report.cpp
  ${_vr}/cli/scene_setup.cpp
  ${_vr}/app/window_update.cpp
  ${_vr}/io/atomic_file.cpp
  ${_vr}/io/cleanup_on_signal.cpp
  ${_vr}/io/exr_io.cpp
  ${_vr}/io/image.cpp
  ${_vr}/io/json_file.cpp
  ${_vr}/io/output_set.cpp
  ${_vr}/io/png_preview.cpp
  ${_vr}/io/text_file.cpp
  ${_vr}/raster/dprsm_check.cpp
  ${_vr}/raster/on_all_cores.cpp
  ${_vr}/raster/tessellate.cpp
  ${_vr}/raster/voxels.cpp
  ${_vr}/render/cpu/cpu_backend.cpp
  ${_vr}/render/cpu/cpu_builders.cpp
  ${_vr}/render/cpu/exact_estimator.cpp
  ${_vr}/render/cpu/ray_scene.cpp
  ${_vr}/render/frame_buffers.cpp
  ${_vr}/render/light_path.cpp
  ${_vr}/render/light_range.cpp
  ${_vr}/render/method_traits.cpp
  ${_vr}/render/lighting_facts.cpp
  ${_vr}/render/running_stage.cpp
  ${_vr}/render/settings.cpp
  ${_vr}/scene/builtin_scenes.cpp
  ${_vr}/scene/camera.cpp
  ${_vr}/scene/framing.cpp
  ${_vr}/scene/mtl_scan.cpp
  ${_vr}/scene/obj_loader.cpp
  ${_vr}/scene/obj_scan.cpp
  ${_vr}/scene/raycast.cpp
  ${_vr}/scene/scene.cpp
  ${_vr}/scene/texture.cpp
  ${_vr}/scene/triangulate.cpp)
target_compile_features(vplrender_core PUBLIC cxx_std_17)
target_include_directories(vplrender_core PUBLIC ${_vr})
target_include_directories(vplrender_core SYSTEM PRIVATE ${VPLRENDER_STB_INCLUDE_DIR})
target_link_libraries(vplrender_core
  PUBLIC vplkit::vplkit glm::glm nlohmann_json::nlohmann_json
  PRIVATE vplkit_project_options tinyobjloader::tinyobjloader OpenEXR::OpenEXR CLI11::CLI11 embree ${VPLRENDER_STB_LIBRARY})
find_package(Threads REQUIRED)
target_link_libraries(vplrender_core PUBLIC Threads::Threads)
set(VPLRENDER_CORE_AVAILABLE ON)

# vplrender_pipeline: the GL stages (rasterisation, GPU voxelisation and scene buffers, the GPU
# backend) and the pipeline that drives both backends; needs the headless GL support library
# (support/, built when examples or GL tests are on).
if(TARGET vplkit_headless_gl)
  add_library(vplrender_pipeline STATIC
    ${_vr}/cli/render_options.cpp
    ${_vr}/raster/dprsm_mesh.cpp
    ${_vr}/raster/gl_mesh.cpp
    ${_vr}/raster/gl_raster.cpp
    ${_vr}/raster/gl_target.cpp
    ${_vr}/raster/gpu_bvh.cpp
    ${_vr}/raster/gpu_scene_buffers.cpp
    ${_vr}/raster/gpu_scene_shading.cpp
    ${_vr}/raster/voxels_gpu.cpp
    ${_vr}/render/gpu/estimate_kernels.cpp
    ${_vr}/render/gpu/gpu_backend.cpp
    ${_vr}/render/gpu/gpu_builders.cpp
    ${_vr}/render/gpu/gpu_cdf.cpp
    ${_vr}/render/gpu/gpu_tiles.cpp
    ${_vr}/render/gpu/gpu_dprsm_planes.cpp
    ${_vr}/render/gpu/gpu_share_tree.cpp
    ${_vr}/render/frames.cpp
    ${_vr}/render/pipeline.cpp)
  target_link_libraries(vplrender_pipeline PUBLIC vplrender_core vplkit::headless_gl PRIVATE vplkit_project_options)
  # The estimate kernels' parameter header (shaders/estimate_params.h) compiles as C++ too.
  target_include_directories(vplrender_pipeline PUBLIC ${CMAKE_CURRENT_LIST_DIR}/shaders)
  # The estimator kernel is read at run time from the source tree (like the pack's kernels).
  target_compile_definitions(vplrender_pipeline PRIVATE
    VPLRENDER_SHADER_DIR="${CMAKE_CURRENT_LIST_DIR}/shaders")
endif()
