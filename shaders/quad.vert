#version 330 core
// A screen-space rectangle (legend strips): rect = (x, y, width, height) in pixels, y down.
uniform vec4 rect;
uniform vec2 viewportSize;
out vec2 uv;
void main() {
  vec2 corner = vec2(gl_VertexID & 1, (gl_VertexID >> 1) & 1);
  vec2 screen = rect.xy + corner * rect.zw;
  uv = corner;
  gl_Position = vec4(screen.x / viewportSize.x * 2.0 - 1.0, 1.0 - screen.y / viewportSize.y * 2.0,
                     0.0, 1.0);
}
