#version 330 core
// A full-viewport triangle with no vertex buffer: gl_VertexID 0, 1, 2 cover the viewport.
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
