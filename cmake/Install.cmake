# `cmake --install BUILD --prefix P`:
#   P/bin/stsv                      the program (shaders embedded; component runtime)
#   P/share/stsv/shaders/           the shader set as embedded, readable (runtime)
#   P/share/doc/stsv/               README.md, LICENSE and docs/, the manual the README links to (runtime)
#   P/include/stsv/MODULE/*.h       the modules' headers (development; cmake/StsvModule.cmake)
#   P/lib/libstsv_MODULE.a          the modules' static libraries (development)
#   P/lib/cmake/stsv/               the CMake package: find_package(stsv CONFIG) (development)
# The component `bundle`, never installed by default, adds the shared libraries the program needs
# to P/lib (cmake/Bundle.cmake, `make bundle`).
include(CMakePackageConfigHelpers)

set(STSV_SHADER_INSTALL_DIR ${CMAKE_INSTALL_DATADIR}/stsv/shaders)
foreach(name path IN ZIP_LISTS STSV_SHADER_SET_NAMES STSV_SHADER_SET_PATHS)
  get_filename_component(folder ${name} DIRECTORY)
  install(FILES ${path} DESTINATION ${STSV_SHADER_INSTALL_DIR}/${folder} COMPONENT runtime)
endforeach()
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/LICENSE DESTINATION ${CMAKE_INSTALL_DOCDIR}
        COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)

set(STSV_CMAKE_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/stsv)
install(EXPORT stsvTargets NAMESPACE stsv:: DESTINATION ${STSV_CMAKE_INSTALL_DIR} COMPONENT development)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/stsvConfig.cmake.in ${PROJECT_BINARY_DIR}/stsvConfig.cmake
                              INSTALL_DESTINATION ${STSV_CMAKE_INSTALL_DIR} PATH_VARS STSV_SHADER_INSTALL_DIR)
# Before 1.0 a minor version may change the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/stsvConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/stsvConfig.cmake ${PROJECT_BINARY_DIR}/stsvConfigVersion.cmake
        DESTINATION ${STSV_CMAKE_INSTALL_DIR} COMPONENT development)
