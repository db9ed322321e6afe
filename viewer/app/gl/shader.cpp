#include "viewer/app/gl/shader.h"

#include "viewer/app/gl/context.h"

#include <glad/gl.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

namespace penumbra {

namespace fs = std::filesystem;

namespace {

std::vector<fs::path> candidateDirectories() {
  std::vector<fs::path> dirs;
  if (const char* env = std::getenv("PENUMBRA_SHADER_DIR"); env && *env) dirs.emplace_back(env);
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    dirs.push_back(exe.parent_path() / "shaders");
    dirs.push_back(exe.parent_path().parent_path() / "share" / "penumbra" / "shaders");
  }
  dirs.emplace_back(PENUMBRA_SHADER_DIR);
  return dirs;
}

std::string readShader(const std::string& name) {
  const fs::path path = fs::path(shaderDirectory()) / name;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw GlError(path.string() + ": cannot read the shader");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The info log of a shader or program (glGetShaderiv/-InfoLog or glGetProgramiv/-InfoLog).
template <class GetIv, class GetLog>
std::string infoLog(GLuint object, GetIv getIv, GetLog getLog) {
  GLint length = 0;
  getIv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(size_t(std::max(length, 1)), '\0');
  getLog(object, length, nullptr, log.data());
  return log;
}

unsigned compile(GLenum type, const std::string& name, const std::vector<ShaderDefine>& defines) {
  const std::string source = injectDefines(readShader(name), defines);
  const GLuint shader = glCreateShader(type);
  const char* text = source.c_str();
  glShaderSource(shader, 1, &text, nullptr);
  glCompileShader(shader);
  GLint ok = 0;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(shader, glGetShaderiv, glGetShaderInfoLog);
    glDeleteShader(shader);
    throw GlError((fs::path(shaderDirectory()) / name).string() + ": compile error:\n" + log);
  }
  return shader;
}

}  // namespace

std::string injectDefines(const std::string& source, const std::vector<ShaderDefine>& defines) {
  if (defines.empty()) return source;
  std::string lines;
  for (const ShaderDefine& d : defines) lines += "#define " + d.name + " " + d.value + "\n";
  const bool versioned = source.rfind("#version", 0) == 0;
  const size_t end = versioned ? source.find('\n') : std::string::npos;
  if (!versioned) return lines + "#line 1\n" + source;
  if (end == std::string::npos) return source + "\n" + lines;
  return source.substr(0, end + 1) + lines + "#line 2\n" + source.substr(end + 1);
}

std::string shaderDirectory() {
  const std::vector<fs::path> dirs = candidateDirectories();
  for (const fs::path& d : dirs) {
    std::error_code ec;
    if (fs::exists(d / "view.frag", ec)) return d.string();
  }
  std::string message = "no shader folder found (view.frag); looked in:";
  for (const fs::path& d : dirs) message += "\n  " + d.string();
  throw GlError(message + "\nset PENUMBRA_SHADER_DIR to the shaders/ folder of the source tree");
}

unsigned buildProgram(const std::string& vertex, const std::string& fragment,
                      const std::vector<ShaderDefine>& defines) {
  const GLuint vs = compile(GL_VERTEX_SHADER, vertex, defines);
  GLuint fsh = 0;
  try {
    fsh = compile(GL_FRAGMENT_SHADER, fragment, defines);
  } catch (...) {
    glDeleteShader(vs);
    throw;
  }
  const GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fsh);
  glLinkProgram(program);
  glDeleteShader(vs);
  glDeleteShader(fsh);
  GLint ok = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) {
    const std::string log = infoLog(program, glGetProgramiv, glGetProgramInfoLog);
    glDeleteProgram(program);
    throw GlError(vertex + " + " + fragment + ": link error:\n" + log);
  }
  return program;
}

}  // namespace penumbra
