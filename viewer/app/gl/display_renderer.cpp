#include "viewer/app/gl/display_renderer.h"

#include "viewer/app/gl/context.h"
#include "viewer/app/gl/shader.h"

#include <glad/gl.h>

#include <algorithm>
#include <initializer_list>
#include <string>
#include <utility>

namespace penumbra {

namespace {

unsigned makeTexture() {
  GLuint t = 0;
  glGenTextures(1, &t);
  glBindTexture(GL_TEXTURE_2D, t);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

// Linear RGB floats into `texture` (`size`: its storage's width and height), stored as
// `format` (GL_RGB32F, or GL_RGB16F where half precision is enough: the display image, whose
// 11-bit mantissa is far finer than the 8-bit picture made of it, in half the memory, which
// llvmpipe keeps in the process). The storage is made only when the size changes, and the
// pixels go in bands of rows, so the driver never holds a second full-size texture or a
// full-size converted copy of the image at once.
void uploadRgb(unsigned texture, TextureSize& size, const Image& image, GLenum format = GL_RGB32F) {
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  if (size.width != image.width || size.height != image.height || size.format != format) {
    glTexImage2D(GL_TEXTURE_2D, 0, GLint(format), image.width, image.height, 0, GL_RGB, GL_FLOAT,
                 nullptr);
    size = {image.width, image.height, unsigned(format)};
  }
  constexpr int kBandRows = 64;
  for (int y = 0; y < image.height; y += kBandRows)
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, y, image.width, std::min(kBandRows, image.height - y),
                    GL_RGB, GL_FLOAT, &image.pixels[size_t(y) * size_t(image.width)]);
}

int uniform(unsigned program, const char* name) { return glGetUniformLocation(program, name); }

// Uses `program` with each texture on the next unit and its sampler uniform set to it.
void useProgram(unsigned program,
                std::initializer_list<std::pair<const char*, unsigned>> textures) {
  glUseProgram(program);
  int unit = 0;
  for (const auto& [sampler, texture] : textures) {
    glActiveTexture(GLenum(GL_TEXTURE0 + unit));
    glBindTexture(GL_TEXTURE_2D, texture);
    glUniform1i(uniform(program, sampler), unit++);
  }
}

}  // namespace

std::vector<ShaderDefine> displayShaderDefines() {
  return {
      {"TONE_CURVE_SRGB", std::to_string(int(ToneCurve::Srgb))},
      {"TONE_CURVE_FILMIC", std::to_string(int(ToneCurve::Filmic))},
      {"SLICE_TEXEL_NONE", std::to_string(int(kSliceTexelNone)) + "u"},
  };
}

DisplayRenderer::DisplayRenderer() {
  std::vector<unsigned> built;
  const std::vector<ShaderDefine> defines = displayShaderDefines();
  try {
    compositeProgram_ = buildProgram("fullscreen.vert", "composite.frag", defines);
    built.push_back(compositeProgram_);
    viewProgram_ = buildProgram("fullscreen.vert", "view.frag", defines);
    built.push_back(viewProgram_);
    quadProgram_ = buildProgram("quad.vert", "quad.frag", defines);
  } catch (...) {
    for (unsigned p : built) glDeleteProgram(p);
    throw;
  }
  glGenVertexArrays(1, &vao_);
  glGenFramebuffers(1, &pictureFbo_);
  picture_ = makeTexture();
  image_ = makeTexture();
  overlay_ = makeTexture();
  slices_ = makeTexture();
  legend_ = makeTexture();
  // Valid 1x1 contents so that a draw before the first upload samples something defined.
  setImage(Image(1, 1));
  setOverlay(Image(1, 1));
  Snapshot empty;
  empty.width = empty.height = 1;
  setSlices(empty);
  width_ = height_ = 0;
}

DisplayRenderer::~DisplayRenderer() {
  const GLuint textures[] = {image_, overlay_, slices_, legend_, picture_};
  glDeleteTextures(5, textures);
  glDeleteFramebuffers(1, &pictureFbo_);
  glDeleteVertexArrays(1, &vao_);
  glDeleteProgram(compositeProgram_);
  glDeleteProgram(viewProgram_);
  glDeleteProgram(quadProgram_);
}

void DisplayRenderer::setImage(const Image& image) {
  if (image.empty()) return;
  uploadRgb(image_, imageSize_, image, GL_RGB16F);
  if (image.width != width_ || image.height != height_) {
    glBindTexture(GL_TEXTURE_2D, picture_);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, image.width, image.height, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, nullptr);
  }
  width_ = image.width;
  height_ = image.height;
  pictureStale_ = true;
}

void DisplayRenderer::setOverlay(const Image& colors) {
  if (!colors.empty()) {
    uploadRgb(overlay_, overlaySize_, colors);
  } else if (overlaySize_.width * overlaySize_.height > 1) {
    setOverlay(Image(1, 1));  // no overlay shown: its texture need not keep a full image
  }
  pictureStale_ = true;
}

void DisplayRenderer::composite(const DisplayView& view) {
  const bool same = !pictureStale_ && view.display.exposure == pictureDisplay_.exposure &&
                    view.display.curve == pictureDisplay_.curve &&
                    view.overlay == pictureOverlay_ && view.blend == pictureBlend_;
  if (same || width_ <= 0 || height_ <= 0) return;
  GLint bound = 0;
  glGetIntegerv(GL_FRAMEBUFFER_BINDING, &bound);
  glBindFramebuffer(GL_FRAMEBUFFER, pictureFbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, picture_, 0);
  glViewport(0, 0, width_, height_);
  const unsigned p = compositeProgram_;
  useProgram(p, {{"image", image_}, {"overlay", overlay_}});
  glUniform1f(uniform(p, "exposure"), view.display.exposure);
  glUniform1i(uniform(p, "curve"), int(view.display.curve));
  glUniform1i(uniform(p, "hasOverlay"), view.overlay ? 1 : 0);
  glUniform1f(uniform(p, "blend"), view.blend);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(bound));
  pictureStale_ = false;
  pictureDisplay_ = view.display;
  pictureOverlay_ = view.overlay;
  pictureBlend_ = view.blend;
}

void DisplayRenderer::clearSlices() {
  if (slicesTexels_ <= 1) return;
  Snapshot empty;
  empty.width = empty.height = 1;
  setSlices(empty);
}

void DisplayRenderer::setSlices(const Snapshot& snapshot) {
  const int width = snapshot.width, height = snapshot.height;
  const size_t n = size_t(width) * height;
  slicesTexels_ = n;
  std::vector<uint8_t> texels(4 * n, kSliceTexelNone);
  // The texel of a slice index: index + 1, kSliceTexelNone (0) for none (-1).
  static_assert(kSliceTexelNone == 0, "a slice index i is stored as i + 1");
  // The maps of slice indices, by their kinds' role: the first in r, the second in g.
  for (const SnapshotMap& map : snapshot.maps) {
    const SliceRole role = map.id.kind()->slices;
    if (role == SliceRole::None) continue;
    const size_t k = role == SliceRole::First ? 0 : 1;
    for (size_t i = 0; i < n && i < map.values.size(); ++i)
      texels[4 * i + k] = uint8_t(int(map.values[i]) + 1);
  }
  if (const SnapshotMap* selected = snapshot.map(maps::Selected))
    for (size_t i = 0; i < n && i < selected->values.size(); ++i)
      texels[4 * i + 2] = uint8_t(selected->values[i]);
  glBindTexture(GL_TEXTURE_2D, slices_);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8UI, width, height, 0, GL_RGBA_INTEGER, GL_UNSIGNED_BYTE,
               texels.data());
}

void DisplayRenderer::setLegend(const Image& strip) {
  legendWidth_ = strip.width;
  legendHeight_ = strip.height;
  if (!strip.empty()) {
    uploadRgb(legend_, legendSize_, strip);
    glBindTexture(GL_TEXTURE_2D, legend_);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  }
}

void DisplayRenderer::draw(int width, int height, const DisplayView& view) {
  if (width <= 0 || height <= 0) return;
  glDisable(GL_BLEND);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_SCISSOR_TEST);
  glBindVertexArray(vao_);
  composite(view);
  glViewport(0, 0, width, height);

  const unsigned p = viewProgram_;
  useProgram(p, {{"picture", picture_}, {"slices", slices_}});
  glUniform2f(uniform(p, "imageSize"), float(width_), float(height_));
  glUniform2f(uniform(p, "viewportSize"), float(width), float(height));
  glUniform2f(uniform(p, "viewCenter"), view.centerX, view.centerY);
  glUniform1f(uniform(p, "zoom"), std::max(view.zoom, 1e-3f));
  glUniform1i(uniform(p, "drawSlices"), view.slices ? 1 : 0);
  glUniform1i(uniform(p, "slicesPerSide"), view.slicesPerSide);
  glUniform2i(uniform(p, "inspected"), view.inspectedX, view.inspectedY);
  glUniform4i(uniform(p, "region"), view.regionX, view.regionY, view.regionWidth,
              view.regionHeight);
  glUniform3f(uniform(p, "background"), 0.12f, 0.12f, 0.13f);
  glDrawArrays(GL_TRIANGLES, 0, 3);

  if (view.legendHeight > 0 && legendHeight_ > 0) {
    const unsigned q = quadProgram_;
    useProgram(q, {{"picture", legend_}});
    glUniform2f(uniform(q, "viewportSize"), float(width), float(height));
    // Drawn at its own size (scaled down to fit), along the bottom edge right of legendLeft.
    const float room = float(std::max(1, width - view.legendLeft));
    const float scale = std::min(1.0f, room / float(std::max(1, legendWidth_)));
    const float w = legendWidth_ * scale, h = legendHeight_ * scale;
    glUniform4f(uniform(q, "rect"), float(view.legendLeft), float(height) - h, w, h);
    glDrawArrays(GL_TRIANGLE_STRIP, 0, 4);
  }
  glBindVertexArray(0);
  glActiveTexture(GL_TEXTURE0);
}

OffscreenTarget::OffscreenTarget(int width, int height) : width_(width), height_(height) {
  if (width <= 0 || height <= 0)
    throw GlError("offscreen target of " + std::to_string(width) + "x" + std::to_string(height));
  glGenFramebuffers(1, &fbo_);
  glGenTextures(1, &color_);
  glBindTexture(GL_TEXTURE_2D, color_);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, width, height, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, color_, 0);
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    throw GlError("offscreen framebuffer incomplete (status " + std::to_string(status) + ")");
}

OffscreenTarget::~OffscreenTarget() {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glDeleteFramebuffers(1, &fbo_);
  glDeleteTextures(1, &color_);
}

void OffscreenTarget::bind() const { glBindFramebuffer(GL_FRAMEBUFFER, fbo_); }

std::vector<uint8_t> OffscreenTarget::read() const {
  bind();
  return readFramebuffer(width_, height_);
}

std::vector<uint8_t> readFramebuffer(int width, int height) {
  std::vector<uint8_t> bottomUp(size_t(width) * height * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, bottomUp.data());
  std::vector<uint8_t> topDown(bottomUp.size());
  const size_t row = size_t(width) * 4;
  for (int y = 0; y < height; ++y)
    std::copy_n(bottomUp.data() + size_t(height - 1 - y) * row, row,
                topDown.data() + size_t(y) * row);
  return topDown;
}

}  // namespace penumbra
