# The shader set and the build-time shader check (DESIGN §5, STYLE §9).
#
# The set is the GLSL of the families' shaders/ folders (render/shaders for what every family's
# passes share, volumes/shaders for STSV, wedges/shaders, shadowmaps/shaders) and every
# device/host header the shaders may include (core/dh.h and the modules' *_dh.h). A file's name
# in the set is its path from the repository's root ("volumes/shaders/stsv.frag",
# "volumes/stsv_dh.h"), so the includes of the sources resolve in it as they do in a checkout. The
# set is embedded in the program (a generated gpu/embedded_shaders.cpp, compiled by
# gpu/shader_compiler.h at run time) and installed, with the same layout, to share/stsv/shaders.
#
# The check: every */shaders/*.{vert,geom,frag,comp,mesh,task} is compiled with glslangValidator
# for Vulkan 1.3 and validated with spirv-val, as part of the default build, so a broken shader
# fails `make`. The SPIR-V lands in the build tree only.
# Shaders with macros (SAMPLE_COUNT, ...) must give them defaults with #ifndef; besides the
# defaults, the variants below compile the define combinations the renderer asks for.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
find_program(SPIRV_VAL spirv-val REQUIRED)

list(TRANSFORM STSV_FAMILIES APPEND /shaders OUTPUT_VARIABLE STSV_SHADER_FOLDERS)
list(PREPEND STSV_SHADER_FOLDERS render/shaders)
set(STSV_SHADER_SOURCES)
set(STSV_SHADER_FOLDER_FILES)
foreach(folder ${STSV_SHADER_FOLDERS})
  file(GLOB sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*.vert ${PROJECT_SOURCE_DIR}/${folder}/*.geom
       ${PROJECT_SOURCE_DIR}/${folder}/*.frag ${PROJECT_SOURCE_DIR}/${folder}/*.comp
       ${PROJECT_SOURCE_DIR}/${folder}/*.mesh ${PROJECT_SOURCE_DIR}/${folder}/*.task)
  file(GLOB files LIST_DIRECTORIES false CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*)
  list(APPEND STSV_SHADER_SOURCES ${sources})
  list(APPEND STSV_SHADER_FOLDER_FILES ${files})
endforeach()

set(STSV_SHADER_OUTPUTS)

file(GLOB STSV_SHADER_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/*/*_dh.h ${PROJECT_SOURCE_DIR}/*/vulkan/*_dh.h)
list(APPEND STSV_SHADER_HEADERS ${PROJECT_SOURCE_DIR}/core/dh.h)
set(STSV_SHADER_SET_NAMES) # names inside the set, sorted
set(STSV_SHADER_SET_PATHS) # the source file of each name, in the same order
set(manifest "")
set(entries)
foreach(path ${STSV_SHADER_FOLDER_FILES} ${STSV_SHADER_HEADERS})
  file(RELATIVE_PATH name ${PROJECT_SOURCE_DIR} ${path})
  list(APPEND entries "${name}\t${path}")
endforeach()
list(REMOVE_DUPLICATES entries)
list(SORT entries)
foreach(entry ${entries})
  string(REPLACE "\t" ";" fields "${entry}")
  list(GET fields 0 name)
  list(GET fields 1 path)
  list(APPEND STSV_SHADER_SET_NAMES ${name})
  list(APPEND STSV_SHADER_SET_PATHS ${path})
  string(APPEND manifest "${name}\t${path}\n")
endforeach()
set(STSV_SHADER_MANIFEST ${PROJECT_BINARY_DIR}/shaders/embedded_shaders.txt)
file(CONFIGURE OUTPUT ${STSV_SHADER_MANIFEST} CONTENT "${manifest}")

# One checked compilation of `source` (a path) with the -D definitions in ARGN; `tag` names the
# variant in the output file (empty: the defaults).
function(stsv_check_shader source tag)
  get_filename_component(name ${source} NAME)
  if(tag)
    set(spv ${PROJECT_BINARY_DIR}/shaders/${name}.${tag}.spv)
  else()
    set(spv ${PROJECT_BINARY_DIR}/shaders/${name}.spv)
  endif()
  set(flags)
  foreach(define IN LISTS ARGN)
    list(APPEND flags "-D${define}")
  endforeach()
  add_custom_command(
    OUTPUT ${spv}
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.3 -I${PROJECT_SOURCE_DIR}
            ${flags} --depfile ${spv}.d -o ${spv} ${source}
    COMMAND ${SPIRV_VAL} --target-env vulkan1.3 ${spv}
    DEPENDS ${source}
    DEPFILE ${spv}.d
    COMMENT "Checking shader ${name} ${tag}"
    VERBATIM)
  set(STSV_SHADER_OUTPUTS ${STSV_SHADER_OUTPUTS} ${spv} PARENT_SCOPE)
endfunction()

foreach(source ${STSV_SHADER_SOURCES})
  stsv_check_shader(${source} "")
endforeach()

# A baked pattern of n points (render/vulkan/gpu_renderer.cpp withPatternDefine: uvec2[n](uvec2(qx, qy), …),
# 24-bit fixed point) for the STSV_PATTERN_Q variants.
function(stsv_pattern_q n out)
  set(points)
  math(EXPR last "${n} - 1")
  foreach(k RANGE ${last})
    math(EXPR qx "(${k} * 262147) % 16777216")
    math(EXPR qy "(${k} * 1048583 + 4099) % 16777216")
    list(APPEND points "uvec2(${qx}u,${qy}u)")
  endforeach()
  list(JOIN points "," joined)
  set(${out} "STSV_PATTERN_Q=uvec2[${n}](${joined})" PARENT_SCOPE)
endfunction()
stsv_pattern_q(16 STSV_Q16)
stsv_pattern_q(64 STSV_Q64)
stsv_pattern_q(128 STSV_Q128)

# The combinations render/vulkan/gpu_renderer.cpp and wedges/vulkan/gpu_wedge_passes.cpp build: SAMPLE_COUNT and
# LS_COUNTERS (--samples, --buffer) on the sample passes; the uniform-buffer layouts
# (STSV_PATTERN_VEC4S, STSV_ALPHA_BIT_VEC4S) on every pass; FIXED_LIGHT_TYPE per light type on
# stsv.frag and resolve.comp; the baked pattern (STSV_PATTERN_Q, ≤ 128 samples) and
# RESOLVE_VCOEF (pw, pw+stsv) on the resolve; STSV_MESH_PATH on stsv.frag behind stsv.mesh and
# WEDGE_MESH_PATH on wedge.frag behind wedge.mesh, HULL_MESH_VOLUMES on the task and mesh shaders;
# STSV_HULL_PATH and WEDGE_HULL_PATH on the fragments behind hull.vert, CLIP_SHARED_INVOCATIONS
# and HULL_ITEMS_PER_THREAD (render/vulkan/gpu_hulls.cpp) on the hull passes; the sample defines and FIXED_LIGHT_TYPE on
# stsv_samples.comp, the sample defines on stsv_merge.comp and wedge_samples.comp; DCS_RAYS_STAGE and DCS_RAY_EDGES on dcs_rays.comp; WEDGE_PW and WEDGE_STSV on the wedge passes; SHADOW_FILTER_STEP on the image-based filter. Each value of each define appears at least once,
# and each sample count with each buffer kind, without the full product (two cores).
set(UBO STSV_PATTERN_VEC4S=128 STSV_ALPHA_BIT_VEC4S=256)
set(S ${PROJECT_SOURCE_DIR}) # the repository, for the lines below
foreach(source volumes/shaders/stsv.vert volumes/shaders/stsv.geom volumes/shaders/stsv.task volumes/shaders/stsv.mesh render/shaders/gbuffer.vert render/shaders/gbuffer.frag
               wedges/shaders/dcs_center.comp wedges/shaders/wedge.geom render/shaders/hull.vert volumes/shaders/stsv_hull.comp
               wedges/shaders/wedge_hull.comp wedges/shaders/wedge.task wedges/shaders/wedge.mesh)
  stsv_check_shader(${S}/${source} ubo ${UBO})
endforeach()

stsv_check_shader(${S}/volumes/shaders/stsv.frag s16_l0 SAMPLE_COUNT=16 FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag s16_counters_l1 SAMPLE_COUNT=16 LS_COUNTERS=1 FIXED_LIGHT_TYPE=1u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag s64_ubo_l2 SAMPLE_COUNT=64 ${UBO} FIXED_LIGHT_TYPE=2u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag s64_counters_l3 SAMPLE_COUNT=64 LS_COUNTERS=1 FIXED_LIGHT_TYPE=3u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag s128_ubo_counters_l0 SAMPLE_COUNT=128 LS_COUNTERS=1 ${UBO} FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag s256_l3 SAMPLE_COUNT=256 FIXED_LIGHT_TYPE=3u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag s256_counters_l2 SAMPLE_COUNT=256 LS_COUNTERS=1 FIXED_LIGHT_TYPE=2u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag mesh_s64_l1 STSV_MESH_PATH=1 SAMPLE_COUNT=64 FIXED_LIGHT_TYPE=1u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag mesh_s256_counters_ubo_l0 STSV_MESH_PATH=1 SAMPLE_COUNT=256 LS_COUNTERS=1 ${UBO}
                  FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag hull_s64_l0 STSV_HULL_PATH=1 SAMPLE_COUNT=64 FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/volumes/shaders/stsv.frag hull_s256_counters_ubo_l2 STSV_HULL_PATH=1 SAMPLE_COUNT=256 LS_COUNTERS=1 ${UBO}
                  FIXED_LIGHT_TYPE=2u)
stsv_check_shader(${S}/volumes/shaders/stsv.mesh volumes1 HULL_MESH_VOLUMES=1)
stsv_check_shader(${S}/wedges/shaders/wedge.mesh volumes3 HULL_MESH_VOLUMES=3)
stsv_check_shader(${S}/volumes/shaders/stsv_hull.comp shared4 CLIP_SHARED_INVOCATIONS=4 HULL_ITEMS_PER_THREAD=16)
stsv_check_shader(${S}/wedges/shaders/wedge_hull.comp shared1_ubo CLIP_SHARED_INVOCATIONS=1 ${UBO})
stsv_check_shader(${S}/volumes/shaders/stsv_samples.comp s16_l1 SAMPLE_COUNT=16 FIXED_LIGHT_TYPE=1u)
stsv_check_shader(${S}/volumes/shaders/stsv_samples.comp s64_counters_ubo_l0 SAMPLE_COUNT=64 LS_COUNTERS=1 ${UBO} FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/volumes/shaders/stsv_samples.comp s256_l3 SAMPLE_COUNT=256 FIXED_LIGHT_TYPE=3u)
stsv_check_shader(${S}/volumes/shaders/stsv_samples.comp s256_counters_l2 SAMPLE_COUNT=256 LS_COUNTERS=1 FIXED_LIGHT_TYPE=2u)
stsv_check_shader(${S}/volumes/shaders/stsv_merge.comp s16 SAMPLE_COUNT=16)
stsv_check_shader(${S}/volumes/shaders/stsv_merge.comp s256_ubo SAMPLE_COUNT=256 ${UBO})

stsv_check_shader(${S}/render/shaders/resolve.comp s16_q_l0 SAMPLE_COUNT=16 "${STSV_Q16}" RESOLVE_VCOEF=0 FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/render/shaders/resolve.comp s16_counters_l2 SAMPLE_COUNT=16 LS_COUNTERS=1 FIXED_LIGHT_TYPE=2u)
stsv_check_shader(${S}/render/shaders/resolve.comp s64_q_l1 SAMPLE_COUNT=64 "${STSV_Q64}" FIXED_LIGHT_TYPE=1u)
stsv_check_shader(${S}/render/shaders/resolve.comp s64_q_counters_ubo_l2 SAMPLE_COUNT=64 LS_COUNTERS=1 "${STSV_Q64}" ${UBO}
                  FIXED_LIGHT_TYPE=2u)
stsv_check_shader(${S}/render/shaders/resolve.comp s64_coverage_l3 SAMPLE_COUNT=64 RESOLVE_VCOEF=1 FIXED_LIGHT_TYPE=3u)
stsv_check_shader(${S}/render/shaders/resolve.comp s128_q_coverage_counters_l0 SAMPLE_COUNT=128 "${STSV_Q128}" RESOLVE_VCOEF=1
                  LS_COUNTERS=1 FIXED_LIGHT_TYPE=0u)
stsv_check_shader(${S}/render/shaders/resolve.comp s128_ubo_l3 SAMPLE_COUNT=128 ${UBO} FIXED_LIGHT_TYPE=3u)
stsv_check_shader(${S}/render/shaders/resolve.comp s256_l1 SAMPLE_COUNT=256 FIXED_LIGHT_TYPE=1u)
stsv_check_shader(${S}/render/shaders/resolve.comp s256_counters_l3 SAMPLE_COUNT=256 LS_COUNTERS=1 FIXED_LIGHT_TYPE=3u)

stsv_check_shader(${S}/wedges/shaders/wedge.frag dcs_s16 WEDGE_PW=0 SAMPLE_COUNT=16 LS_COUNTERS=1)
stsv_check_shader(${S}/wedges/shaders/wedge.frag dcs_s256_ubo WEDGE_PW=0 SAMPLE_COUNT=256 LS_COUNTERS=1 ${UBO})
stsv_check_shader(${S}/wedges/shaders/wedge.frag pw WEDGE_PW=1 WEDGE_STSV=0)
stsv_check_shader(${S}/wedges/shaders/wedge.frag pw_stsv_ubo WEDGE_PW=1 WEDGE_STSV=1 ${UBO})
stsv_check_shader(${S}/wedges/shaders/wedge.frag hull_dcs_s64 WEDGE_HULL_PATH=1 WEDGE_PW=0 SAMPLE_COUNT=64 LS_COUNTERS=1)
stsv_check_shader(${S}/wedges/shaders/wedge.frag hull_pw_ubo WEDGE_HULL_PATH=1 WEDGE_PW=1 ${UBO})
stsv_check_shader(${S}/wedges/shaders/wedge.frag mesh_dcs_s64 WEDGE_MESH_PATH=1 WEDGE_PW=0 SAMPLE_COUNT=64 LS_COUNTERS=1)
stsv_check_shader(${S}/wedges/shaders/wedge.frag mesh_pw_ubo WEDGE_MESH_PATH=1 WEDGE_PW=1 ${UBO})
stsv_check_shader(${S}/wedges/shaders/wedge_samples.comp s16 SAMPLE_COUNT=16 LS_COUNTERS=1)
stsv_check_shader(${S}/wedges/shaders/wedge_samples.comp s256_ubo SAMPLE_COUNT=256 LS_COUNTERS=1 ${UBO})
stsv_check_shader(${S}/wedges/shaders/dcs_rays.comp list_s16 DCS_RAYS_STAGE=0 SAMPLE_COUNT=16 DCS_RAY_EDGES=0.5)
stsv_check_shader(${S}/wedges/shaders/dcs_rays.comp rays_s256_ubo DCS_RAYS_STAGE=1 SAMPLE_COUNT=256 DCS_RAY_EDGES=1e+09 ${UBO})
stsv_check_shader(${S}/wedges/shaders/wedge_fold.comp dcs_s16 WEDGE_PW=0 SAMPLE_COUNT=16 LS_COUNTERS=1)
stsv_check_shader(${S}/wedges/shaders/wedge_fold.comp dcs_s256_ubo WEDGE_PW=0 SAMPLE_COUNT=256 LS_COUNTERS=1 ${UBO})
stsv_check_shader(${S}/wedges/shaders/wedge_fold.comp pw WEDGE_PW=1 WEDGE_STSV=0 SAMPLE_COUNT=64)
stsv_check_shader(${S}/wedges/shaders/wedge_fold.comp pw_stsv_s256 WEDGE_PW=1 WEDGE_STSV=1 SAMPLE_COUNT=256)
stsv_check_shader(${S}/wedges/shaders/wedge_fold.comp pw_stsv_s16_counters WEDGE_PW=1 WEDGE_STSV=1 SAMPLE_COUNT=16 LS_COUNTERS=1)

# The image-based passes: the map raster with the uniform layouts; SHADOW_FILTER_STEP 1, 2 (PCSS).
stsv_check_shader(${S}/shadowmaps/shaders/shadowmap.vert ubo ${UBO})
stsv_check_shader(${S}/shadowmaps/shaders/shadowmap.frag ubo ${UBO})
stsv_check_shader(${S}/shadowmaps/shaders/shadow_filter.comp pcss_blocker SHADOW_FILTER_STEP=1)
stsv_check_shader(${S}/shadowmaps/shaders/shadow_filter.comp pcss_filter_ubo SHADOW_FILTER_STEP=2 ${UBO})
# The transmittance functions: the lists with alpha bits (a frame without translucent
# triangles), and the steps of avsm and vpcss.
stsv_check_shader(${S}/shadowmaps/shaders/avsm_fragments.frag ubo ${UBO})
stsv_check_shader(${S}/shadowmaps/shaders/shadow_filter.comp avsm_lookup SHADOW_FILTER_STEP=4)
stsv_check_shader(${S}/shadowmaps/shaders/shadow_filter.comp vpcss_blocker SHADOW_FILTER_STEP=5)
stsv_check_shader(${S}/shadowmaps/shaders/shadow_filter.comp vpcss_filter_ubo SHADOW_FILTER_STEP=6 ${UBO})
# peel's march with lanes sharing a pixel (PEEL_LANES, PEEL_GROUP: shadowmaps/vulkan/gpu_shadowmap_passes.cpp).
stsv_check_shader(${S}/shadowmaps/shaders/peel_march.comp s256_lanes4 SAMPLE_COUNT=256 PEEL_LANES=4 PEEL_GROUP=64)
stsv_check_shader(${S}/shadowmaps/shaders/peel_march.comp s256_counters_lanes256 SAMPLE_COUNT=256 LS_COUNTERS=1 PEEL_LANES=256 PEEL_GROUP=256)

file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/shaders)
add_custom_target(stsv_shaders ALL DEPENDS ${STSV_SHADER_OUTPUTS})
