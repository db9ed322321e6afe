#version 330 core
// Dear ImGui's fragments: the font atlas (or an image) times the vertex colour.
uniform sampler2D atlas;
in vec2 uv;
in vec4 tint;
out vec4 fragColor;
void main() { fragColor = tint * texture(atlas, uv); }
