// Draws Dear ImGui's draw lists with our own shaders (shaders/imgui.*) through glad, so the
// panel and the inspector render in the GLFW window and in both headless contexts alike
// (ImGui's packaged OpenGL backend loads GL from libGL and fails under OSMesa).
#pragma once

struct ImDrawData;

namespace penumbra {

class ImGuiRenderer {
 public:
  ImGuiRenderer();  // needs a current context and ImGui's context; uploads the font atlas
  ~ImGuiRenderer();
  ImGuiRenderer(const ImGuiRenderer&) = delete;
  ImGuiRenderer& operator=(const ImGuiRenderer&) = delete;
  // Draws into the bound framebuffer of framebufferWidth x framebufferHeight pixels.
  void render(const ImDrawData* data, int framebufferWidth, int framebufferHeight);

 private:
  unsigned program_ = 0, vao_ = 0, vbo_ = 0, ibo_ = 0, font_ = 0;
};

}  // namespace penumbra
