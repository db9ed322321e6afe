#version 330 core
// Draws a texture of linear RGB (a legend strip drawn by the engine) sRGB encoded.
uniform sampler2D picture;
in vec2 uv;
out vec4 fragColor;
float srgbEncode(float v) {
  if (!(v > 0.0)) return 0.0;
  if (v >= 1.0) return 1.0;
  return v <= 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
}
void main() {
  vec3 c = texture(picture, uv).rgb;
  fragColor = vec4(srgbEncode(c.r), srgbEncode(c.g), srgbEncode(c.b), 1.0);
}
