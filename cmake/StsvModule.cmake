# stsv_module(NAME DEPS ...): a static library from every .cpp in the calling folder.
# Headers are included as "folder/file.h" from the repository root.
set(STSV_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion -Werror)
# GCC 12 at -O3 reports -Wrestrict inside libstdc++'s std::string (GCC bugs 105329 and 105651,
# fixed in 13): a warning there, never an error, so every build type builds.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  list(APPEND STSV_WARNINGS -Wno-error=restrict)
endif()

function(stsv_module name)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  add_library(stsv_${name} STATIC ${sources})
  target_include_directories(stsv_${name} PUBLIC ${PROJECT_SOURCE_DIR})
  target_compile_options(stsv_${name} PRIVATE ${STSV_WARNINGS})
  target_compile_definitions(stsv_${name} PUBLIC GLM_FORCE_XYZW_ONLY GLM_ENABLE_EXPERIMENTAL
                             STSV_SOURCE_DIR="${PROJECT_SOURCE_DIR}")
  target_link_libraries(stsv_${name} PUBLIC ${ARG_DEPS})
endfunction()

# stsv_tests(MODULE DEPS ...): tests/MODULE/*.cpp into one GoogleTest executable test_MODULE.
function(stsv_tests module)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${module}/*.cpp)
  if(NOT sources)
    return()
  endif()
  add_executable(test_${module} ${sources})
  target_compile_options(test_${module} PRIVATE ${STSV_WARNINGS})
  target_link_libraries(test_${module} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(test_${module} PRIVATE STSV_TEST_DATA="${CMAKE_CURRENT_SOURCE_DIR}/data")
  gtest_discover_tests(test_${module} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS ${module})
endfunction()
