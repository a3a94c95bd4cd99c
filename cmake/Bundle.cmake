# Script mode (cmake -P), `make bundle`: the relocatable bundle of a finished build.
#   -DBUILD_DIR=DIR    the build tree          -DOUTPUT_DIR=DIR  where the .tar.gz goes (dist)
# Writes OUTPUT_DIR/stsv-VERSION-linux-ARCH.tar.gz, one folder of that name holding bin/stsv,
# lib/ with every shared library the program needs except the C library family and the Vulkan
# loader (found through the program's $ORIGIN/../lib run path), share/stsv/shaders, README.md,
# LICENSE and docs/ (so the README's links work in the unpacked folder). Fails when a library of
# the folder would be looked up outside it.
cmake_minimum_required(VERSION 3.25)
foreach(var BUILD_DIR OUTPUT_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "Bundle.cmake needs -D${var}=...")
  endif()
endforeach()
file(REAL_PATH ${BUILD_DIR} BUILD_DIR)
set(program ${BUILD_DIR}/cli/stsv)
if(NOT EXISTS ${program})
  message(FATAL_ERROR "${program} is missing: build first (make build)")
endif()

execute_process(COMMAND ${program} --version OUTPUT_VARIABLE version OUTPUT_STRIP_TRAILING_WHITESPACE
                COMMAND_ERROR_IS_FATAL ANY)
string(REGEX REPLACE "^stsv " "" version "${version}")
execute_process(COMMAND uname -m OUTPUT_VARIABLE arch OUTPUT_STRIP_TRAILING_WHITESPACE COMMAND_ERROR_IS_FATAL ANY)
set(name stsv-${version}-linux-${arch})
set(stage ${BUILD_DIR}/bundle)
set(root ${stage}/${name})
file(REMOVE_RECURSE ${stage})

foreach(component runtime bundle)
  execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${root} --component ${component} --strip
                  OUTPUT_QUIET COMMAND_ERROR_IS_FATAL ANY)
endforeach()
file(RENAME ${root}/share/doc/stsv/README.md ${root}/README.md)
file(RENAME ${root}/share/doc/stsv/LICENSE ${root}/LICENSE)
file(RENAME ${root}/share/doc/stsv/docs ${root}/docs)
file(REMOVE_RECURSE ${root}/share/doc)

# Every library the loader would look up for the program must resolve into lib/ or be one the
# target machine provides; ldd sees the same run path the loader uses.
execute_process(COMMAND ldd ${root}/bin/stsv OUTPUT_VARIABLE ldd COMMAND_ERROR_IS_FATAL ANY)
string(REPLACE "\n" ";" lines "${ldd}")
set(bundled)
foreach(line IN LISTS lines)
  if(line MATCHES "^[ \t]*([^ ]+) => ([^ ]+)")
    set(library ${CMAKE_MATCH_1})
    set(resolved ${CMAKE_MATCH_2})
    if(library MATCHES "^(libc|libm|libdl|libpthread|librt|libresolv|libutil|libvulkan)\\.so")
      continue()
    endif()
    file(REAL_PATH ${resolved} resolved_real)
    file(REAL_PATH ${root}/lib lib_real)
    string(FIND "${resolved_real}" "${lib_real}/" inside)
    if(NOT inside EQUAL 0)
      message(FATAL_ERROR "bundle: ${library} resolves to ${resolved}, outside the bundle's lib/")
    endif()
    list(APPEND bundled ${library})
  endif()
endforeach()

# The oldest glibc the bundle runs on: the newest GLIBC_ symbol version its files ask for.
set(glibc "2.0")
file(GLOB_RECURSE binaries ${root}/bin/* ${root}/lib/*)
foreach(binary IN LISTS binaries)
  if(IS_SYMLINK ${binary})
    continue()
  endif()
  execute_process(COMMAND objdump -T ${binary} OUTPUT_VARIABLE symbols ERROR_QUIET)
  string(REGEX MATCHALL "GLIBC_[0-9]+\\.[0-9]+(\\.[0-9]+)?" needs "${symbols}")
  foreach(need IN LISTS needs)
    string(REPLACE "GLIBC_" "" need ${need})
    if(need VERSION_GREATER glibc)
      set(glibc ${need})
    endif()
  endforeach()
endforeach()

file(MAKE_DIRECTORY ${OUTPUT_DIR})
file(REAL_PATH ${OUTPUT_DIR} OUTPUT_DIR)
set(archive ${OUTPUT_DIR}/${name}.tar.gz)
execute_process(COMMAND ${CMAKE_COMMAND} -E tar czf ${archive} ${name} WORKING_DIRECTORY ${stage}
                COMMAND_ERROR_IS_FATAL ANY)
list(JOIN bundled " " bundled)
message(STATUS "wrote ${archive}")
message(STATUS "  bundled: ${bundled}")
message(STATUS "  needs on the target: glibc >= ${glibc}, a Vulkan 1.3 loader (libvulkan.so.1) and driver")
