// GLSL programs from the files in shaders/: found at run time ($PENUMBRA_SHADER_DIR, next to
// the executable, or the source tree of the build), compiled with #defines from the C++ side
// and linked, with errors that name the file and carry the compiler's log.
#pragma once

#include <string>
#include <vector>

namespace penumbra {

// The folder the shaders are read from (the first that holds view.frag).
std::string shaderDirectory();

// A `#define NAME VALUE` the C++ side gives a shader: the shaders compare with the C++
// enums' values through these, never with numbers of their own (like tev's shader defines).
struct ShaderDefine {
  std::string name, value;
};

// `source` with one `#define` line per entry after its `#version` line (at the top when it
// has none), followed by `#line 2`, so the compiler's line numbers are still the file's.
std::string injectDefines(const std::string& source, const std::vector<ShaderDefine>& defines);

// Compiles and links shaders/<vertex> and shaders/<fragment>, both with `defines` injected;
// throws GlError naming the file ("view.frag: compile error: <log>") when one is missing or
// broken.
unsigned buildProgram(const std::string& vertex, const std::string& fragment,
                      const std::vector<ShaderDefine>& defines = {});

}  // namespace penumbra
