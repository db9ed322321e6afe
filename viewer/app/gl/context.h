// OpenGL contexts for the viewer. The window gets its context from GLFW (view_app); headless
// rendering makes one here, with no display and no X server:
//  - EGL on a GPU device (EGL_EXT_device_enumeration), where a GPU driver offers one;
//  - EGL on Mesa's surfaceless platform (llvmpipe on the CPU);
//  - OSMesa, the fallback.
// Every backend draws into the viewer's own framebuffer object, so the same drawing code
// and shaders serve the window and the screenshots. All load GL through glad.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

namespace penumbra {

struct GlError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class HeadlessBackend { Auto, Egl, OsMesa };

class HeadlessContext {
 public:
  virtual ~HeadlessContext() = default;
  // What was created, e.g. "egl surfaceless (llvmpipe ...)" or "osmesa (...)".
  virtual std::string description() const = 0;
  virtual const char* backendName() const = 0;  // "egl" or "osmesa"
};

// Creates a current OpenGL 3.3 core context with glad loaded. Auto tries EGL (device, then
// surfaceless), then OSMesa. Throws GlError listing every attempt and why it failed.
std::unique_ptr<HeadlessContext> createHeadlessContext(HeadlessBackend backend);

// Loads GL through glad with `getProcAddress` and checks that the context is at least 3.3
// core; throws GlError naming `where` otherwise. Returns "GL version, renderer".
using GlProcLoader = void (*(*)(const char*))();
std::string loadGl(GlProcLoader getProcAddress, const std::string& where);

}  // namespace penumbra
