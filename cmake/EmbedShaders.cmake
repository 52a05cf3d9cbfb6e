# embed_shaders(TARGET DIR): compiles every shader under DIR (*.glsl, *.vert, *.frag) into
# TARGET as byte arrays (viewer/embedded_shaders.h), so the installed binary needs no shader
# files. The table is regenerated when a shader changes; a new shader file re-runs the
# configure step (CONFIGURE_DEPENDS). Run with `cmake -P` (SHADER_DIR, OUTPUT set) it writes
# the generated source itself.
if(CMAKE_SCRIPT_MODE_FILE)
  file(GLOB shader_files RELATIVE ${SHADER_DIR} ${SHADER_DIR}/*.glsl ${SHADER_DIR}/*.vert
       ${SHADER_DIR}/*.frag)
  list(SORT shader_files)
  set(arrays "")
  set(table "")
  foreach(file IN LISTS shader_files)
    file(READ ${SHADER_DIR}/${file} hex HEX)
    file(SIZE ${SHADER_DIR}/${file} size)
    # Bytes, not a string literal: any character in a shader survives, and no length limit.
    string(REGEX REPLACE "([0-9a-f][0-9a-f])" "'\\\\x\\1'," bytes "${hex}")
    string(MAKE_C_IDENTIFIER "${file}" name)
    string(APPEND arrays "constexpr char ${name}[] = {${bytes}'\\0'};\n")
    string(APPEND table "    {\"${file}\", {${name}, ${size}}},\n")
  endforeach()
  file(WRITE ${OUTPUT}.tmp
       "// Generated from ${SHADER_DIR} by cmake/EmbedShaders.cmake; do not edit.\n"
       "#include \"viewer/embedded_shaders.h\"\n\n"
       "namespace lb {\n\nnamespace {\n\n${arrays}\n"
       "constexpr EmbeddedShader shaders[] = {\n${table}};\n\n}  // namespace\n\n"
       "std::span<const EmbeddedShader> embedded_shaders() {\n  return shaders;\n}\n\n"
       "}  // namespace lb\n")
  # Unchanged text keeps its timestamp, so a comment edit elsewhere rebuilds nothing.
  file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
  file(REMOVE ${OUTPUT}.tmp)
  return()
endif()

function(embed_shaders target dir)
  file(GLOB shader_files CONFIGURE_DEPENDS ${dir}/*.glsl ${dir}/*.vert ${dir}/*.frag)
  set(output ${CMAKE_CURRENT_BINARY_DIR}/embedded_shaders.cpp)
  add_custom_command(
    OUTPUT ${output}
    COMMAND ${CMAKE_COMMAND} -DSHADER_DIR=${dir} -DOUTPUT=${output}
            -P ${PROJECT_SOURCE_DIR}/cmake/EmbedShaders.cmake
    DEPENDS ${shader_files} ${PROJECT_SOURCE_DIR}/cmake/EmbedShaders.cmake
    COMMENT "Embedding the shaders of ${dir}"
    VERBATIM)
  target_sources(${target} PRIVATE ${output})
endfunction()
