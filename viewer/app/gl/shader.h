// GLSL programs from the files in shaders/: found at run time ($PENUMBRA_SHADER_DIR, next to
// the executable, or the source tree of the build), compiled and linked with errors that
// name the file and carry the compiler's log.
#pragma once

#include <string>

namespace penumbra {

// The folder the shaders are read from (the first that holds view.frag).
std::string shaderDirectory();

// Compiles and links shaders/<vertex> and shaders/<fragment>; throws GlError naming the file
// ("view.frag: compile error: <log>") when one is missing or broken.
unsigned buildProgram(const std::string& vertex, const std::string& fragment);

}  // namespace penumbra
