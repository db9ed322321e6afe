#version 330 core
// The viewer's picture at image resolution, redrawn only when the image or a display
// setting changes: exposure, tone curve and sRGB encoding of the linear render, then the
// overlay blended in display space. engine/present/overlays.cpp (displayTransform, composePixel) is
// the CPU reference of these formulas; view.frag then shows the result zoomed and panned.
// The upper-case names are #defines the viewer injects from its C++ enums
// (viewer/app/gl/display_renderer.cpp, displayShaderDefines).

uniform sampler2D image;    // linear RGB, one texel per pixel
uniform sampler2D overlay;  // overlay colours, linear RGB
uniform float exposure;     // stops
uniform int curve;          // TONE_CURVE_SRGB or TONE_CURVE_FILMIC (ToneCurve's values)
uniform bool hasOverlay;
uniform float blend;

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
  if (curve == TONE_CURVE_FILMIC) x = isinf(x) ? 1.0 : filmic(x);
  return srgbEncode(x);
}

void main() {
  // The target has the image's size and rows top first, like the textures.
  ivec2 texel = ivec2(gl_FragCoord.xy);
  vec3 linear = texelFetch(image, texel, 0).rgb;
  float scale = exp2(exposure);
  vec3 color = vec3(displayChannel(linear.r, scale), displayChannel(linear.g, scale),
                    displayChannel(linear.b, scale));
  if (hasOverlay) {
    float b = clamp(blend, 0.0, 1.0);
    vec3 o = texelFetch(overlay, texel, 0).rgb;
    color = color * (1.0 - b) + vec3(srgbEncode(o.r), srgbEncode(o.g), srgbEncode(o.b)) * b;
  }
  fragColor = vec4(color, 1.0);
}
