// Draws the viewer's picture with the shaders of shaders/, into whatever framebuffer is
// bound (the window's or an offscreen one): the image through the display transform with
// the overlay blended in, composited at image resolution only when something changed
// (composite.frag), then shown zoomed and panned every frame (view.frag), and the legend
// strip along the bottom (quad.frag). Textures are uploaded only when the caller hands over
// new data.
#pragma once

#include "present/overlays.h"
#include "viewer/app/gl/shader.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace penumbra {

// The slices texture holds per pixel slice B + 1, slice C + 1 and the selected flag; this
// texel value is "no slice" (the shaders' SLICE_TEXEL_NONE).
inline constexpr uint8_t kSliceTexelNone = 0;

// The #defines the display shaders are compiled with, from the C++ enums and constants above
// (ToneCurve, kSliceTexelNone): the GLSL code uses these names, never numbers of its own.
std::vector<ShaderDefine> displayShaderDefines();

// The storage of a texture: its size and internal format (0 before any).
struct TextureSize {
  int width = 0, height = 0;
  unsigned format = 0;
};

struct DisplayView {
  float zoom = 1.0f;               // screen pixels per image pixel
  float centerX = 0, centerY = 0;  // image position at the viewport centre
  DisplaySettings display;
  bool overlay = false;  // blend the overlay texture in
  float blend = 0.7f;
  bool slices = false;  // outline slices and fill B and C (when zoomed in)
  int slicesPerSide = 0;
  int inspectedX = -1, inspectedY = -1;
  // The render region, outlined just outside its pixels; width 0: none.
  int regionX = 0, regionY = 0, regionWidth = 0, regionHeight = 0;
  int legendHeight = 0;  // bottom band left for the legend strip
  int legendLeft = 0;    // where the strip starts (right of the panel)
};

class DisplayRenderer {
 public:
  DisplayRenderer();  // needs a current GL 3.3 context; throws GlError on a shader error
  ~DisplayRenderer();
  DisplayRenderer(const DisplayRenderer&) = delete;
  DisplayRenderer& operator=(const DisplayRenderer&) = delete;

  void setImage(const Image& image);
  // Linear RGB, the image's size; empty: none shown (the texture shrinks to one texel).
  void setOverlay(const Image& colors);
  // Per pixel: slice B, slice C (-1 none) and the selected flag of the last round, from the
  // snapshot's SliceB, SliceC and Selected maps (none where it lacks one).
  void setSlices(const Snapshot& snapshot);
  void clearSlices();                  // none drawn: the texture shrinks to one texel
  void setLegend(const Image& strip);  // empty: none

  // Draws into the bound framebuffer's viewport of width x height (both > 0).
  void draw(int width, int height, const DisplayView& view);

 private:
  void composite(const DisplayView& view);

  unsigned compositeProgram_ = 0, viewProgram_ = 0, quadProgram_ = 0, vao_ = 0;
  unsigned image_ = 0, overlay_ = 0, slices_ = 0, legend_ = 0;
  unsigned picture_ = 0, pictureFbo_ = 0;  // the composited picture, image-sized
  int width_ = 0, height_ = 0;
  int legendWidth_ = 0, legendHeight_ = 0;
  TextureSize imageSize_, overlaySize_, legendSize_;  // their storage
  size_t slicesTexels_ = 0;                           // of the slices texture
  // What the picture was composited from; a difference recomposites it.
  bool pictureStale_ = true;
  DisplaySettings pictureDisplay_;
  bool pictureOverlay_ = false;
  float pictureBlend_ = -1.0f;
};

// A framebuffer object of RGBA8 for headless drawing and screenshots.
class OffscreenTarget {
 public:
  OffscreenTarget(int width, int height);
  ~OffscreenTarget();
  OffscreenTarget(const OffscreenTarget&) = delete;
  OffscreenTarget& operator=(const OffscreenTarget&) = delete;
  void bind() const;
  int width() const { return width_; }
  int height() const { return height_; }
  // RGBA, top row first.
  std::vector<uint8_t> read() const;

 private:
  unsigned fbo_ = 0, color_ = 0;
  int width_, height_;
};

// The bound framebuffer's pixels (RGBA8, top row first) of a width x height viewport.
std::vector<uint8_t> readFramebuffer(int width, int height);

}  // namespace penumbra
