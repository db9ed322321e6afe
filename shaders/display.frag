#version 330 core
// The viewer's image: exposure, tone curve and sRGB encoding of the linear render, then the
// overlay blended in display space, with nearest-neighbour magnification, the slices B and C
// of the last round when zoomed in (Selected overlay), and the inspected pixel outlined.
// engine/overlays.cpp (displayTransform, composePixel) is the CPU reference of these formulas.

uniform sampler2D image;      // linear RGB, one texel per pixel
uniform sampler2D overlay;    // overlay colours, linear RGB
uniform usampler2D slices;    // r: slice B + 1, g: slice C + 1 (0: none), b: selected
uniform vec2 imageSize;
uniform vec2 viewportSize;
uniform vec2 viewCenter;      // image position at the viewport centre
uniform float zoom;           // screen pixels per image pixel
uniform float exposure;       // stops
uniform int curve;            // 0: sRGB, 1: filmic
uniform int hasOverlay;
uniform float blend;
uniform int drawSlices;       // outline slices and fill B and C (zoomed in)
uniform int slicesPerSide;
uniform ivec2 inspected;      // (-1, -1): none
uniform vec3 background;

out vec4 fragColor;

float srgbEncode(float v) {
  if (!(v > 0.0)) return 0.0;
  if (v >= 1.0) return 1.0;
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}

float filmic(float x) {
  if (!(x > 0.0)) return 0.0;
  float y = (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
  return clamp(y, 0.0, 1.0);
}

float displayChannel(float linear, float scale) {
  if (isnan(linear)) return 0.0;
  float x = linear * scale;
  if (curve == 1) x = isinf(x) ? 1.0 : filmic(x);
  return srgbEncode(x);
}

vec3 srgb(vec3 c) { return vec3(srgbEncode(c.r), srgbEncode(c.g), srgbEncode(c.b)); }

void main() {
  vec2 screen = vec2(gl_FragCoord.x, viewportSize.y - gl_FragCoord.y);
  vec2 pos = viewCenter + (screen - 0.5 * viewportSize) / zoom;
  if (pos.x < 0.0 || pos.y < 0.0 || pos.x >= imageSize.x || pos.y >= imageSize.y) {
    fragColor = vec4(background, 1.0);
    return;
  }
  ivec2 texel = ivec2(floor(pos));
  vec3 linear = texelFetch(image, texel, 0).rgb;
  float scale = exp2(exposure);
  vec3 color = vec3(displayChannel(linear.r, scale), displayChannel(linear.g, scale),
                    displayChannel(linear.b, scale));
  if (hasOverlay == 1) {
    float b = clamp(blend, 0.0, 1.0);
    color = color * (1.0 - b) + srgb(texelFetch(overlay, texel, 0).rgb) * b;
  }
  vec2 local = pos - vec2(texel);  // position inside the pixel, [0,1)^2, y down
  // Lines one screen pixel wide: the distance to a border in screen pixels.
  if (drawSlices == 1 && slicesPerSide > 0) {
    uvec4 s = texelFetch(slices, texel, 0);
    float n = float(slicesPerSide);
    ivec2 cell = ivec2(floor(local * n));
    int slice = cell.x + slicesPerSide * cell.y;
    if (s.r > 0u && slice == int(s.r) - 1) color = mix(color, vec3(0.25, 0.55, 1.0), 0.45);
    if (s.g > 0u && slice == int(s.g) - 1) color = mix(color, vec3(1.0, 0.55, 0.1), 0.45);
    vec2 toLine = abs(fract(local * n + 0.5) - 0.5) / n * zoom;
    if (min(toLine.x, toLine.y) < 0.5) color = mix(color, vec3(0.6), 0.6);
  }
  if (inspected.x >= 0 && texel == inspected) {
    vec2 toEdge = min(local, 1.0 - local) * zoom;
    if (min(toEdge.x, toEdge.y) < max(1.0, min(3.0, 0.08 * zoom))) color = vec3(1.0, 0.2, 0.9);
  }
  fragColor = vec4(color, 1.0);
}
