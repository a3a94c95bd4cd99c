# stsv_module(NAME DEPS ...): a static library from every .cpp in the calling folder.
# Headers are included as "folder/file.h" from the repository root.
set(STSV_WARNINGS -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Wno-sign-conversion)
if(STSV_WERROR)
  list(APPEND STSV_WARNINGS -Werror)
endif()
# GCC 12 at -O3 reports -Wrestrict inside libstdc++'s std::string (GCC bugs 105329 and 105651,
# fixed in 13): a warning there, never an error, so every build type builds.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  list(APPEND STSV_WARNINGS -Wno-error=restrict)
endif()

# __FILE__ names sources from the repository root ("gpu/buffer.cpp"): error messages read the same
# on every machine, and the program holds no path of the checkout it was built from.
set(STSV_PREFIX_MAP "-fmacro-prefix-map=${PROJECT_SOURCE_DIR}/=")

include(GNUInstallDirs)

# Static library stsv_NAME (stsv::NAME, in the build and in the installed CMake package) from
# every .cpp in the calling folder (or SOURCES), with the folder's headers (or HEADERS) installed
# to include/stsv/DIR (DIR defaults to NAME: "render/cpu" for the library render_cpu). FAMILIES:
# folders from the repository root ("wedges/cpu") whose .cpp join the library and whose headers
# install to include/stsv/FOLDER: a backend's library holds each family's side of that backend,
# which lives in the family's folder.
function(stsv_module name)
  cmake_parse_arguments(ARG "" "DIR" "DEPS;SOURCES;HEADERS;FAMILIES" ${ARGN})
  if(ARG_SOURCES)
    list(TRANSFORM ARG_SOURCES PREPEND ${CMAKE_CURRENT_SOURCE_DIR}/ OUTPUT_VARIABLE sources)
  else()
    file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  endif()
  if(ARG_HEADERS)
    list(TRANSFORM ARG_HEADERS PREPEND ${CMAKE_CURRENT_SOURCE_DIR}/ OUTPUT_VARIABLE headers)
  else()
    file(GLOB headers CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.h)
  endif()
  if(NOT ARG_DIR)
    set(ARG_DIR ${name})
  endif()
  foreach(folder IN LISTS ARG_FAMILIES)
    file(GLOB family_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*.cpp)
    file(GLOB family_headers CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/${folder}/*.h)
    list(APPEND sources ${family_sources})
    install(FILES ${family_headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/stsv/${folder} COMPONENT development)
  endforeach()
  add_library(stsv_${name} STATIC ${sources})
  add_library(stsv::${name} ALIAS stsv_${name})
  set_target_properties(stsv_${name} PROPERTIES EXPORT_NAME ${name})
  target_include_directories(stsv_${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
                                                 $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/stsv>)
  target_compile_options(stsv_${name} PRIVATE ${STSV_WARNINGS} ${STSV_PREFIX_MAP})
  target_compile_definitions(stsv_${name} PUBLIC GLM_FORCE_XYZW_ONLY GLM_ENABLE_EXPERIMENTAL)
  target_link_libraries(stsv_${name} PUBLIC ${ARG_DEPS})
  install(TARGETS stsv_${name} EXPORT stsvTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          COMPONENT development)
  install(FILES ${headers} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/stsv/${ARG_DIR} COMPONENT development)
endfunction()

# stsv_tests(MODULE DEPS ...): tests/MODULE/*.cpp into one GoogleTest executable test_MODULE.
function(stsv_tests module)
  cmake_parse_arguments(ARG "" "" "DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${module}/*.cpp)
  if(NOT sources)
    message(FATAL_ERROR "stsv_tests(${module}): tests/${module}/ holds no test sources")
  endif()
  add_executable(test_${module} ${sources})
  target_compile_options(test_${module} PRIVATE ${STSV_WARNINGS})
  target_link_libraries(test_${module} PRIVATE ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(
    test_${module} PRIVATE STSV_TEST_DATA="${CMAKE_CURRENT_SOURCE_DIR}/data" STSV_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
                           STSV_TEST_IMAGES_DIR="${PROJECT_BINARY_DIR}/Testing/Temporary/images")
  gtest_discover_tests(test_${module} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS ${module})
endfunction()
