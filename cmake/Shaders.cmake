# Build-time shader check (DESIGN §5, STYLE §9): every shaders/*.{vert,geom,frag,comp,mesh,task}
# is compiled with glslangValidator for Vulkan 1.3 and validated with spirv-val, as part of the
# default build, so a broken shader fails `make`. The SPIR-V lands in the build tree only; the
# program compiles shaders at run time (gpu/shader_compiler.h) with the same include rules.
# Shaders with macros (SAMPLE_COUNT, ...) must give them defaults with #ifndef.
find_program(GLSLANG_VALIDATOR glslangValidator REQUIRED)
find_program(SPIRV_VAL spirv-val REQUIRED)

file(GLOB STSV_SHADER_SOURCES CONFIGURE_DEPENDS
     ${PROJECT_SOURCE_DIR}/shaders/*.vert ${PROJECT_SOURCE_DIR}/shaders/*.geom
     ${PROJECT_SOURCE_DIR}/shaders/*.frag ${PROJECT_SOURCE_DIR}/shaders/*.comp
     ${PROJECT_SOURCE_DIR}/shaders/*.mesh ${PROJECT_SOURCE_DIR}/shaders/*.task)

set(STSV_SHADER_OUTPUTS)
foreach(source ${STSV_SHADER_SOURCES})
  get_filename_component(name ${source} NAME)
  set(spv ${PROJECT_BINARY_DIR}/shaders/${name}.spv)
  add_custom_command(
    OUTPUT ${spv}
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.3 -I${PROJECT_SOURCE_DIR} -I${PROJECT_SOURCE_DIR}/shaders
            --depfile ${spv}.d -o ${spv} ${source}
    COMMAND ${SPIRV_VAL} --target-env vulkan1.3 ${spv}
    DEPENDS ${source}
    DEPFILE ${spv}.d
    COMMENT "Checking shader ${name}"
    VERBATIM)
  list(APPEND STSV_SHADER_OUTPUTS ${spv})
endforeach()

file(MAKE_DIRECTORY ${PROJECT_BINARY_DIR}/shaders)
add_custom_target(stsv_shaders ALL DEPENDS ${STSV_SHADER_OUTPUTS})
