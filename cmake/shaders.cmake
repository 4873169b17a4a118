# Compiles every GLSL file in shaders/ to SPIR-V and embeds it as a C array
# (glslangValidator --vn) in a generated header, so binaries carry their shaders.
file(GLOB RTSDF_SHADER_SOURCES CONFIGURE_DEPENDS
  ${PROJECT_SOURCE_DIR}/shaders/*.vert
  ${PROJECT_SOURCE_DIR}/shaders/*.frag
  ${PROJECT_SOURCE_DIR}/shaders/*.comp)
file(GLOB RTSDF_SHADER_HEADERS CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/shaders/*.h)

set(RTSDF_SPIRV_DIR ${PROJECT_BINARY_DIR}/spirv)
file(MAKE_DIRECTORY ${RTSDF_SPIRV_DIR})
set(RTSDF_SPIRV_HEADERS)
foreach(src ${RTSDF_SHADER_SOURCES})
  get_filename_component(name ${src} NAME)
  string(REPLACE "." "_" symbol "spirv_${name}")
  set(out ${RTSDF_SPIRV_DIR}/${symbol}.h)
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${GLSLANG_VALIDATOR} -V --target-env vulkan1.2 -I${PROJECT_SOURCE_DIR}/shaders
            --vn ${symbol} -o ${out} ${src}
    DEPENDS ${src} ${RTSDF_SHADER_HEADERS}
    COMMENT "glslang ${name}"
    VERBATIM)
  list(APPEND RTSDF_SPIRV_HEADERS ${out})
endforeach()
add_custom_target(rtsdf_shaders DEPENDS ${RTSDF_SPIRV_HEADERS})
