#version 330 core
// Shows the composited picture (composite.frag) in the viewport: nearest-neighbour zoom and
// pan, the slices of the last round with B and C filled when zoomed in (Selected overlay),
// the inspected pixel outlined, and the render region outlined. Cheap per fragment, so it can run every frame.
// SLICE_TEXEL_NONE is a #define the viewer injects from its C++ constant (kSliceTexelNone).

uniform sampler2D picture;    // display-encoded colours, one texel per image pixel
uniform usampler2D slices;    // r: slice B + 1, g: slice C + 1 (SLICE_TEXEL_NONE: none)
uniform vec2 imageSize;
uniform vec2 viewportSize;
uniform vec2 viewCenter;      // image position at the viewport centre
uniform float zoom;           // screen pixels per image pixel
uniform bool drawSlices;
uniform int slicesPerSide;
uniform ivec2 inspected;      // (-1, -1): none
uniform ivec4 region;         // x, y, width, height in image pixels; width 0: none
uniform vec3 background;

out vec4 fragColor;

void main() {
  vec2 screen = vec2(gl_FragCoord.x, viewportSize.y - gl_FragCoord.y);
  vec2 pos = viewCenter + (screen - 0.5 * viewportSize) / zoom;
  if (pos.x < 0.0 || pos.y < 0.0 || pos.x >= imageSize.x || pos.y >= imageSize.y) {
    fragColor = vec4(background, 1.0);
    return;
  }
  ivec2 texel = ivec2(floor(pos));
  vec3 color = texelFetch(picture, texel, 0).rgb;
  vec2 local = pos - vec2(texel);  // position inside the pixel, [0,1)^2, y down
  if (drawSlices && slicesPerSide > 0) {
    uvec4 s = texelFetch(slices, texel, 0);
    float n = float(slicesPerSide);
    ivec2 cell = ivec2(floor(local * n));
    int slice = cell.x + slicesPerSide * cell.y;
    if (s.r != SLICE_TEXEL_NONE && slice == int(s.r) - 1)
      color = mix(color, vec3(0.25, 0.55, 1.0), 0.45);
    if (s.g != SLICE_TEXEL_NONE && slice == int(s.g) - 1)
      color = mix(color, vec3(1.0, 0.55, 0.1), 0.45);
    // Lines about one screen pixel wide on the slice borders.
    vec2 toLine = abs(fract(local * n + 0.5) - 0.5) / n * zoom;
    if (min(toLine.x, toLine.y) < 0.6) color = mix(color, vec3(0.6), 0.6);
  }
  if (inspected.x >= 0 && texel == inspected) {
    vec2 toEdge = min(local, 1.0 - local) * zoom;
    if (min(toEdge.x, toEdge.y) < max(1.0, min(3.0, 0.08 * zoom))) color = vec3(1.0, 0.2, 0.9);
  }
  if (region.z > 0) {
    // A line about 1.5 screen pixels wide just outside the region's pixels.
    vec2 lo = vec2(region.xy), hi = vec2(region.xy + region.zw);
    vec2 outside = max(lo - pos, pos - hi) * zoom;  // screen pixels beyond each edge
    bool alongX = pos.y >= lo.y - 1.5 / zoom && pos.y <= hi.y + 1.5 / zoom;
    bool alongY = pos.x >= lo.x - 1.5 / zoom && pos.x <= hi.x + 1.5 / zoom;
    if ((alongX && outside.x > 0.0 && outside.x <= 1.5) ||
        (alongY && outside.y > 0.0 && outside.y <= 1.5))
      color = vec3(1.0, 0.75, 0.2);
  }
  fragColor = vec4(color, 1.0);
}
