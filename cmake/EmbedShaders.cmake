# Script mode (cmake -P): writes the C++ source that embeds the shader set in the program.
#   -DMANIFEST=FILE  lines "NAME<TAB>PATH": NAME is the file's path inside the set, PATH its source
#   -DOUTPUT=FILE    the generated source (the build runs this only when a listed file changed)
# Each file becomes a raw string literal; the script fails if a file contains the delimiter.
cmake_minimum_required(VERSION 3.25)
set(delimiter "stsv_embedded")
file(STRINGS ${MANIFEST} entries)
set(body "")
foreach(entry IN LISTS entries)
  string(REPLACE "\t" ";" fields "${entry}")
  list(GET fields 0 name)
  list(GET fields 1 path)
  file(READ ${path} text)
  string(FIND "${text}" ")${delimiter}\"" clash)
  if(NOT clash EQUAL -1)
    message(FATAL_ERROR "${path} contains ')${delimiter}\"', the delimiter of the embedded shader set")
  endif()
  string(APPEND body "    {\"${name}\", R\"${delimiter}(${text})${delimiter}\"},\n")
endforeach()
set(source "// Generated from ${MANIFEST} by cmake/EmbedShaders.cmake; do not edit.
#include \"gpu/shader_compiler.h\"

namespace stsv {
namespace {
constexpr ShaderFile kEmbeddedShaders[] = {
${body}};
} // namespace

std::span<const ShaderFile> embeddedShaders() {
    return kEmbeddedShaders;
}

} // namespace stsv
")
file(WRITE ${OUTPUT} "${source}")
