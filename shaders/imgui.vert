#version 330 core
// Dear ImGui's vertices: position in screen pixels, texture coordinates, colour.
uniform mat4 projection;
layout(location = 0) in vec2 position;
layout(location = 1) in vec2 texCoord;
layout(location = 2) in vec4 color;
out vec2 uv;
out vec4 tint;
void main() {
  uv = texCoord;
  tint = color;
  gl_Position = projection * vec4(position, 0.0, 1.0);
}
