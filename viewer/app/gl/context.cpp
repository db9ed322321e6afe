#include "viewer/app/gl/context.h"

#include <glad/gl.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/osmesa.h>

#include <cstring>
#include <vector>

namespace penumbra {

namespace {

std::string eglErrorName(EGLint e) {
  switch (e) {
    case EGL_SUCCESS:
      return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED:
      return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS:
      return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC:
      return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE:
      return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG:
      return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT:
      return "EGL_BAD_CONTEXT";
    case EGL_BAD_DISPLAY:
      return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH:
      return "EGL_BAD_MATCH";
    case EGL_BAD_PARAMETER:
      return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE:
      return "EGL_BAD_SURFACE";
    default:
      return "EGL error " + std::to_string(e);
  }
}

bool hasExtension(const char* list, const char* name) {
  if (!list) return false;
  const size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)); p += n)
    if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0')) return true;
  return false;
}

class EglContext final : public HeadlessContext {
 public:
  EglContext(EGLDisplay display, EGLContext context, EGLSurface surface, std::string description)
      : display_(display),
        context_(context),
        surface_(surface),
        description_(std::move(description)) {}
  ~EglContext() override {
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
    eglDestroyContext(display_, context_);
    eglTerminate(display_);
  }
  void setDescription(std::string d) { description_ = std::move(d); }
  std::string description() const override { return description_; }
  const char* backendName() const override { return "egl"; }

 private:
  EGLDisplay display_;
  EGLContext context_;
  EGLSurface surface_;
  std::string description_;
};

GLADapiproc eglLoader(const char* name) { return GLADapiproc(eglGetProcAddress(name)); }

// A 3.3 core context on an initialised display; throws GlError with `what` on failure.
std::unique_ptr<HeadlessContext> eglContextOn(EGLDisplay display, const std::string& what) {
  EGLint major = 0, minor = 0;
  if (!eglInitialize(display, &major, &minor))
    throw GlError(what + ": eglInitialize failed (" + eglErrorName(eglGetError()) + ")");
  auto fail = [&](const std::string& why) {
    eglTerminate(display);
    throw GlError(what + ": " + why);
  };
  if (!eglBindAPI(EGL_OPENGL_API))
    fail("no desktop OpenGL API (" + eglErrorName(eglGetError()) + ")");
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  const bool surfaceless = hasExtension(extensions, "EGL_KHR_surfaceless_context");
  const EGLint configAttribs[] = {EGL_SURFACE_TYPE,
                                  surfaceless ? 0 : EGL_PBUFFER_BIT,
                                  EGL_RENDERABLE_TYPE,
                                  EGL_OPENGL_BIT,
                                  EGL_RED_SIZE,
                                  8,
                                  EGL_GREEN_SIZE,
                                  8,
                                  EGL_BLUE_SIZE,
                                  8,
                                  EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (!eglChooseConfig(display, configAttribs, &config, 1, &count) || count < 1)
    fail("no OpenGL-capable EGL config (" + eglErrorName(eglGetError()) + ")");
  const EGLint contextAttribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                                   3,
                                   EGL_CONTEXT_MINOR_VERSION,
                                   3,
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                   EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, contextAttribs);
  if (context == EGL_NO_CONTEXT)
    fail("cannot create an OpenGL 3.3 core context (" + eglErrorName(eglGetError()) + ")");
  EGLSurface surface = EGL_NO_SURFACE;
  if (!surfaceless) {
    const EGLint pbufferAttribs[] = {EGL_WIDTH, 16, EGL_HEIGHT, 16, EGL_NONE};
    surface = eglCreatePbufferSurface(display, config, pbufferAttribs);
    if (surface == EGL_NO_SURFACE) {
      eglDestroyContext(display, context);
      fail("cannot create a pbuffer (" + eglErrorName(eglGetError()) + ")");
    }
  }
  if (!eglMakeCurrent(display, surface, surface, context)) {
    if (surface != EGL_NO_SURFACE) eglDestroySurface(display, surface);
    eglDestroyContext(display, context);
    fail("eglMakeCurrent failed (" + eglErrorName(eglGetError()) + ")");
  }
  auto owned = std::make_unique<EglContext>(display, context, surface, what);
  const std::string gl = loadGl(eglLoader, what);  // `owned` cleans up if this throws
  owned->setDescription(what + ", EGL " + std::to_string(major) + "." + std::to_string(minor) +
                        ", " + gl);
  return owned;
}

std::unique_ptr<HeadlessContext> createEgl(std::vector<std::string>& tried) {
  // A GPU first: EGL devices other than Mesa's software one.
  auto queryDevices =
      reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  auto queryDeviceString = reinterpret_cast<PFNEGLQUERYDEVICESTRINGEXTPROC>(
      eglGetProcAddress("eglQueryDeviceStringEXT"));
  auto platformDisplay = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!platformDisplay) {
    tried.push_back("egl: eglGetPlatformDisplayEXT is missing");
    return nullptr;
  }
  if (queryDevices && queryDeviceString) {
    EGLDeviceEXT devices[16];
    EGLint count = 0;
    if (queryDevices(16, devices, &count)) {
      for (EGLint i = 0; i < count; ++i) {
        const char* ext = queryDeviceString(devices[i], EGL_EXTENSIONS);
        if (hasExtension(ext, "EGL_MESA_device_software")) continue;
        const std::string what = "egl device " + std::to_string(i);
        EGLDisplay display = platformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr);
        if (display == EGL_NO_DISPLAY) {
          tried.push_back(what + ": no display (" + eglErrorName(eglGetError()) + ")");
          continue;
        }
        try {
          return eglContextOn(display, what);
        } catch (const GlError& e) {
          tried.push_back(e.what());
        }
      }
    }
  }
  EGLDisplay display = platformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) {
    tried.push_back("egl surfaceless: no display (" + eglErrorName(eglGetError()) + ")");
    return nullptr;
  }
  try {
    return eglContextOn(display, "egl surfaceless");
  } catch (const GlError& e) {
    tried.push_back(e.what());
  }
  return nullptr;
}

class OsMesaContext final : public HeadlessContext {
 public:
  OsMesaContext(OSMesaContext context, std::string description)
      : context_(context), buffer_(4 * 16 * 16), description_(std::move(description)) {}
  ~OsMesaContext() override { OSMesaDestroyContext(context_); }
  bool makeCurrent() {
    return OSMesaMakeCurrent(context_, buffer_.data(), GL_UNSIGNED_BYTE, 16, 16);
  }
  void setDescription(std::string d) { description_ = std::move(d); }
  std::string description() const override { return description_; }
  const char* backendName() const override { return "osmesa"; }

 private:
  OSMesaContext context_;
  std::vector<unsigned char> buffer_;  // the default framebuffer; we draw into our own FBO
  std::string description_;
};

GLADapiproc osmesaLoader(const char* name) { return GLADapiproc(OSMesaGetProcAddress(name)); }

std::unique_ptr<HeadlessContext> createOsMesa(std::vector<std::string>& tried) {
  const int attribs[] = {OSMESA_FORMAT,
                         OSMESA_RGBA,
                         OSMESA_DEPTH_BITS,
                         0,
                         OSMESA_PROFILE,
                         OSMESA_CORE_PROFILE,
                         OSMESA_CONTEXT_MAJOR_VERSION,
                         3,
                         OSMESA_CONTEXT_MINOR_VERSION,
                         3,
                         0};
  OSMesaContext context = OSMesaCreateContextAttribs(attribs, nullptr);
  if (!context) {
    tried.push_back("osmesa: cannot create an OpenGL 3.3 core context");
    return nullptr;
  }
  auto owned = std::make_unique<OsMesaContext>(context, "osmesa");
  if (!owned->makeCurrent()) {
    tried.push_back("osmesa: OSMesaMakeCurrent failed");
    return nullptr;
  }
  try {
    owned->setDescription("osmesa, " + loadGl(osmesaLoader, "osmesa"));
  } catch (const GlError& e) {
    tried.push_back(e.what());
    return nullptr;
  }
  return owned;
}

}  // namespace

std::string loadGl(GlProcLoader getProcAddress, const std::string& where) {
  const int version = gladLoadGL(reinterpret_cast<GLADloadfunc>(getProcAddress));
  if (version == 0) throw GlError(where + ": cannot load OpenGL functions");
  if (GLAD_VERSION_MAJOR(version) * 10 + GLAD_VERSION_MINOR(version) < 33)
    throw GlError(where + ": OpenGL " + std::to_string(GLAD_VERSION_MAJOR(version)) + "." +
                  std::to_string(GLAD_VERSION_MINOR(version)) + " is below the 3.3 needed");
  const char* v = reinterpret_cast<const char*>(glGetString(GL_VERSION));
  const char* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  return std::string("OpenGL ") + (v ? v : "?") + ", " + (r ? r : "?");
}

std::unique_ptr<HeadlessContext> createHeadlessContext(HeadlessBackend backend) {
  std::vector<std::string> tried;
  if (backend != HeadlessBackend::OsMesa)
    if (auto c = createEgl(tried)) return c;
  if (backend != HeadlessBackend::Egl)
    if (auto c = createOsMesa(tried)) return c;
  std::string message = "no headless OpenGL context could be created:";
  for (const std::string& t : tried) message += "\n  " + t;
  throw GlError(message);
}

}  // namespace penumbra
