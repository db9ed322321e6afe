// The viewer's Dear ImGui windows: the panel (method and parameters, progress and timings,
// display, overlays, the MSE plot, controls and saving) and the pixel inspector (why a pixel
// got its samples).
#include "viewer/app/view_panel.h"

#include "eval/metrics.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace penumbra {

namespace {

ImU32 toU32(vec3 srgb, float alpha = 1.0f) {
  return ImGui::ColorConvertFloat4ToU32(ImVec4(srgb.x, srgb.y, srgb.z, alpha));
}

// One widget for a parameter of a table, its help as the tooltip; true when it changed.
template <typename Config>
bool paramControl(const Param<Config>& p, Config& config);

template <typename Config>
bool paramWidget(const Param<Config>& p, Config& config) {
  const bool changed = paramControl(p, config);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", p.help.c_str());
  return changed;
}

template <typename Config>
bool paramControl(const Param<Config>& p, Config& config) {
  const char* label = p.label.c_str();
  const ImGuiSliderFlags scale = p.logarithmic ? ImGuiSliderFlags_Logarithmic : 0;
  const auto accept = [&](double v) {
    p.set(config, std::clamp(v, p.min, p.max));
    return true;
  };
  switch (p.kind) {
    case ParamKind::Int: {
      if (p.field) {
        double v = p.get(config);
        return ImGui::InputDouble(label, &v, 1, 100, "%.0f") && accept(std::round(v));
      }
      int v = int(p.get(config));
      return ImGui::SliderInt(label, &v, int(p.uiMin), int(p.uiMax)) && accept(v);
    }
    case ParamKind::Float: {
      if (p.field) {
        double v = p.get(config);
        return ImGui::InputDouble(label, &v, 0, 0, "%.4g") && accept(v);
      }
      float v = float(p.get(config));
      return ImGui::SliderFloat(label, &v, float(p.uiMin), float(p.uiMax), "%.3f", scale) &&
             accept(v);
    }
    case ParamKind::Flag: {
      bool v = p.get(config) != 0;
      if (!ImGui::Checkbox(label, &v)) return false;
      p.set(config, v ? 1 : 0);
      return true;
    }
    case ParamKind::Choice: {
      int v = int(p.get(config));
      std::string items;
      for (const std::string& c : p.choices) items += c + '\0';
      if (!ImGui::Combo(label, &v, items.c_str())) return false;
      p.set(config, v);
      return true;
    }
    case ParamKind::FloatList: {
      std::vector<float> values = p.getList(config);
      bool changed = false;
      for (size_t i = 0; i < values.size(); ++i) {
        const std::string item = p.label + " " + std::to_string(i + 1);
        changed |= ImGui::SliderFloat(item.c_str(), &values[i], float(p.uiMin), float(p.uiMax),
                                      "%.2f", scale);
        values[i] = float(std::clamp(double(values[i]), p.min, p.max));
      }
      if (changed) p.setList(config, values);
      return changed;
    }
  }
  return false;
}

// The method by name, and its presets: a preset switches to its algorithm and resets that
// method's configuration to the preset. True when something changed.
bool methodChoice(ViewOptions& o) {
  bool changed = false;
  if (ImGui::BeginCombo("method", o.method->name().c_str())) {
    for (const std::string& name : o.methods->names()) {
      const MethodDescriptor* first = o.methods->find(name);
      const std::string label = name + " - " + first->description();
      if (ImGui::Selectable(label.c_str(), name == o.method->name())) {
        o.method = first;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  bool first = true;
  for (const auto& [method, preset] : o.methods->presetsOf(o.method->name())) {
    if (!first) ImGui::SameLine();
    first = false;
    const std::string label = preset->name + " preset";
    if (ImGui::Button(label.c_str())) {
      o.method = method;
      o.config() = method->defaults();
      preset->apply(o.config());
      changed = true;
    }
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", preset->help.c_str());
  }
  return changed;
}

}  // namespace

std::vector<const Param<RunShape>*> runWidgets() {
  std::vector<const Param<RunShape>*> out;
  for (const Param<RunShape>& p : runShapeParams().params())
    if (p.scope & kViewCommand) out.push_back(&p);
  return out;
}

std::vector<ParamSection> methodSections(const ViewOptions& options) {
  std::vector<ParamSection> sections;
  for (const MethodParam& p : options.method->params()) {
    if (sections.empty() || sections.back().title != p.group) sections.push_back({p.group, {}});
    sections.back().params.push_back(&p);
  }
  return sections;
}

namespace {

// The method, the run's shape and every parameter of the method's table, grouped as the
// table groups them; true when something changed.
bool methodParameters(ViewOptions& o) {
  bool changed = methodChoice(o);
  for (const Param<RunShape>* p : runWidgets()) changed |= paramWidget(*p, o.shape);
  MethodConfig& config = o.config();
  for (const ParamSection& section : methodSections(o)) {
    if (!ImGui::TreeNode(section.title.c_str())) continue;
    for (const MethodParam* p : section.params) changed |= paramWidget(*p, config);
    ImGui::TreePop();
  }
  return changed;
}

// The overlay's value at pixel index i (its units on hover).
void overlayValue(const OverlayImage& ov, size_t i) {
  if (ov.legend.kind == ColorMapKind::Rgb)
    ImGui::Text("%s: %.4g %.4g %.4g", ov.label.c_str(), ov.values[3 * i], ov.values[3 * i + 1],
                ov.values[3 * i + 2]);
  else
    ImGui::Text("%s: %.4g", ov.label.c_str(), ov.values[i]);
  if (!ov.legend.units.empty() && ImGui::IsItemHovered())
    ImGui::SetTooltip("%s", ov.legend.units.c_str());
}

void progress(const RenderSession& session, const Snapshot& s) {
  const double pixels = std::max(1.0, double(s.width) * s.height);
  ImGui::Text("%s  round %d  %s", s.method.c_str(), s.round, toString(session.state()));
  ImGui::Text("kept %.2f spp, traced %.2f spp", double(s.keptSamples) / pixels,
              double(s.tracedSamples) / pixels);
  const double mrays = s.seconds > 0 ? double(s.rays) / s.seconds * 1e-6 : 0.0;
  ImGui::Text("%.2f s, %.2f Mrays/s", s.seconds, mrays);
  ImGui::Text("trace %.2f  train %.2f  select %.2f  reconstruct %.2f  network %.2f s",
              s.times.trace, s.times.train, s.times.select, s.times.reconstruct, s.times.network);
  if (s.nonFiniteSamples)
    ImGui::Text("%llu NaN/inf samples dropped", (unsigned long long)s.nonFiniteSamples);
}

// MSE against kept spp on log-log axes (the paper's Fig. 7), with the decades labelled.
void msePlot(const std::vector<std::pair<double, double>>& history) {
  const ImVec2 size(ImGui::GetContentRegionAvail().x, 110.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y),
                      IM_COL32(25, 25, 30, 255));
  double x0 = 1e30, x1 = -1e30, y0 = 1e30, y1 = -1e30;
  for (const auto& [spp, mse] : history) {
    if (!(spp > 0) || !(mse > 0)) continue;
    x0 = std::min(x0, std::log10(spp));
    x1 = std::max(x1, std::log10(spp));
    y0 = std::min(y0, std::log10(mse));
    y1 = std::max(y1, std::log10(mse));
  }
  if (x0 > x1) {
    ImGui::Dummy(size);
    return;
  }
  // Whole decades around the data, at least one wide.
  x0 = std::floor(x0);
  x1 = std::max(std::ceil(x1), x0 + 1);
  y0 = std::floor(y0);
  y1 = std::max(std::ceil(y1), y0 + 1);
  const float left = 44, bottom = 16;
  auto at = [&](double lx, double ly) {
    return ImVec2(origin.x + left + float((lx - x0) / (x1 - x0)) * (size.x - left - 6),
                  origin.y + 4 + float((y1 - ly) / (y1 - y0)) * (size.y - bottom - 8));
  };
  char label[32];
  for (double d = y0; d <= y1 + 1e-9; d += 1) {
    const ImVec2 p = at(x0, d);
    draw->AddLine(p, at(x1, d), IM_COL32(70, 70, 80, 255));
    std::snprintf(label, sizeof label, "1e%d", int(d));
    draw->AddText(ImVec2(origin.x + 2, p.y - 7), IM_COL32(180, 180, 180, 255), label);
  }
  for (double d = x0; d <= x1 + 1e-9; d += 1) {
    const ImVec2 p = at(d, y0);
    draw->AddLine(at(d, y1), p, IM_COL32(70, 70, 80, 255));
    std::snprintf(label, sizeof label, "%g", std::pow(10.0, d));
    const float textWidth = ImGui::CalcTextSize(label).x;
    const float x = std::min(p.x - 0.5f * textWidth, origin.x + size.x - textWidth - 2);
    draw->AddText(ImVec2(x, origin.y + size.y - bottom + 1), IM_COL32(180, 180, 180, 255), label);
  }
  ImVec2 previous{};
  bool have = false;
  for (const auto& [spp, mse] : history) {
    if (!(spp > 0) || !(mse > 0)) continue;
    const ImVec2 p = at(std::log10(spp), std::log10(mse));
    if (have) draw->AddLine(previous, p, IM_COL32(250, 200, 60, 255), 1.5f);
    draw->AddCircleFilled(p, 2.0f, IM_COL32(250, 200, 60, 255));
    previous = p;
    have = true;
  }
  ImGui::Dummy(size);
  ImGui::TextDisabled("MSE against kept spp, log-log");
}

}  // namespace

void drawPanel(const PanelState& state, const PanelActions& actions) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSizeConstraints(ImVec2(340, 0),
                                      ImVec2(340, ImGui::GetIO().DisplaySize.y - 16));
  ImGui::SetNextWindowBgAlpha(0.85f);
  if (!ImGui::Begin("Penumbra")) {
    ImGui::End();
    return;
  }
  ViewOptions& o = state.options;
  ViewState& v = state.view;
  const auto snap = state.snapshot;
  if (ImGui::CollapsingHeader("Progress", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (snap)
      progress(state.session, *snap);
    else
      ImGui::TextUnformatted("waiting for the first round");
    if (state.firstPictureSeconds >= 0)
      ImGui::Text("first picture %.0f ms after the last restart", state.firstPictureSeconds * 1e3);
    const FrameStats& f = state.frameStats;
    ImGui::Text("UI frame %.1f ms (p95 %.1f ms)", f.lastSeconds * 1e3, f.percentile(0.95) * 1e3);
    const bool paused = state.session.state() == RenderSession::State::Paused;
    if (ImGui::Button(paused ? "resume" : "pause")) {
      if (paused)
        state.session.resume();
      else
        state.session.pause();
    }
    ImGui::SameLine();
    if (ImGui::Button("one round")) state.session.step();
    ImGui::SameLine();
    if (ImGui::Button("restart")) actions.restart();
  }
  if (ImGui::CollapsingHeader("Method", ImGuiTreeNodeFlags_DefaultOpen)) {
    if (methodParameters(o)) actions.restart();
    if (!state.configError.empty())
      ImGui::TextColored(ImVec4(1, 0.4f, 0.4f, 1), "%s", state.configError.c_str());
  }
  if (ImGui::CollapsingHeader("Display", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::SliderFloat("exposure", &o.display.exposure, -10.0f, 10.0f, "%.1f stops");
    int curve = o.display.curve == ToneCurve::Filmic ? 1 : 0;
    if (ImGui::Combo("tone", &curve, "sRGB\0filmic\0"))
      o.display.curve = curve ? ToneCurve::Filmic : ToneCurve::Srgb;
    if (ImGui::Checkbox("raw estimate (no reconstruction)", &o.showRaw))
      actions.shownImageChanged();
    int current = 0;
    const auto list = overlayList(*o.methods);
    for (size_t i = 0; i < list.size(); ++i)
      if (MapId(*list[i]) == o.overlay) current = int(i) + 1;
    std::string items = std::string("none") + '\0';
    for (const MapKind* kind : list) items += std::string(kind->panelLabel) + '\0';
    if (ImGui::Combo("overlay", &current, items.c_str()))
      actions.setOverlay(current == 0 ? MapId() : MapId(*list[size_t(current - 1)]));
    ImGui::SliderFloat("blend", &o.blend, 0.0f, 1.0f, "%.2f");
    if (!o.overlay.none() && !state.overlay.available())
      ImGui::TextColored(ImVec4(1, 0.7f, 0.3f, 1), "%s", state.overlay.unavailable.c_str());
    ImGui::Text("zoom %.2fx", v.zoom);
    float ix, iy;
    v.toImage(v.cursorX, v.cursorY, ix, iy);
    const int px = int(std::floor(ix)), py = int(std::floor(iy));
    if (snap && px >= 0 && py >= 0 && px < snap->width && py < snap->height) {
      const vec3 c = shownImage(*state.snapshot, o).at(px, py);
      ImGui::Text("pixel (%d, %d): %.4g %.4g %.4g", px, py, c.x, c.y, c.z);
      const OverlayImage& ov = state.overlay;
      if (ov.available()) overlayValue(ov, size_t(py) * snap->width + px);
    }
  }
  if (o.reference && ImGui::CollapsingHeader("Reference", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::TextUnformatted(o.referencePath.c_str());
    const auto& h = state.mseHistory;
    if (!h.empty()) {
      ImGui::Text("MSE %.3e at %.1f spp", h.back().second, h.back().first);
      msePlot(h);
    }
  }
  if (ImGui::CollapsingHeader("Scene")) {
    // Edits to the scene's files reload by themselves; another file opens here or by dropping
    // it on the window.
    ImGui::TextWrapped("%s", o.scenePath.empty() ? "(no file)" : o.scenePath.c_str());
    ImGui::InputText("file", v.openField, sizeof v.openField);
    if (ImGui::Button("open scene (.json/.gltf/.glb/.obj)") && v.openField[0])
      actions.openScene(v.openField);
  }
  if (ImGui::CollapsingHeader("Environment")) {
    // The map that lights the scene (an equirectangular .exr or .hdr, top row up), its
    // strength and its turn about +y; "none" removes it. A change restarts the render.
    const Environment& e = o.scene->scene.environment;
    ImGui::TextWrapped("%s", !e.present() ? "(none)"
                             : e.builtin  ? "(built-in studio)"
                                          : e.file.c_str());
    ImGui::InputText("map file", v.environmentField, sizeof v.environmentField);
    bool changed = false;
    std::string file;  // empty: keep the map
    if (ImGui::Button("use this map (or none)") && v.environmentField[0]) {
      changed = true;
      file = v.environmentField;
    }
    changed |= ImGui::DragFloat("strength", &v.environmentStrength, 0.01f, 0.0f, 1e4f, "%.3g",
                                ImGuiSliderFlags_AlwaysClamp);
    changed |= ImGui::SliderFloat("rotation", &v.environmentRotation, -180.0f, 180.0f, "%.0f deg");
    if (changed) actions.setEnvironment({file, v.environmentStrength, v.environmentRotation});
  }
  if (ImGui::CollapsingHeader("Render region")) {
    // Ctrl + left drag on the image draws one; ctrl + click clears it.
    ImGui::InputInt4("x, y, w, h", v.regionField);
    if (ImGui::Button("render only this"))
      actions.setRegion({v.regionField[0], v.regionField[1], v.regionField[2], v.regionField[3]});
    ImGui::SameLine();
    if (ImGui::Button("render everything")) actions.setRegion({});
  }
  if (ImGui::CollapsingHeader("Save")) {
    ImGui::InputText("image", v.savePath, sizeof v.savePath);
    if (ImGui::Button("save image (.exr/.png)"))
      state.message = actions.saveImage(o.saveDirectory + "/" + v.savePath);
    ImGui::InputText("screenshot", v.screenshotField, sizeof v.screenshotField);
    if (ImGui::Button("save screenshot"))
      actions.requestScreenshot(o.saveDirectory + "/" + v.screenshotField);
  }
  if (ImGui::CollapsingHeader("Keys", v.showHelp ? ImGuiTreeNodeFlags_DefaultOpen : 0)) {
    ImGui::Text(
        "1-%zu overlays (all in the list above), 0 none, [ ] blend\n"
        "R raw/reconstructed, "
        "-/= exposure, T tone curve, F fit, scroll zoom\n"
        "middle or shift+left drag: pan the image\n"
        "left drag: orbit, right drag: pan the camera\n"
        "ctrl+scroll: dolly, WASD QE: fly\n"
        "click: inspect a pixel, I inspector, Tab panel\n"
        "ctrl+left drag: render region, ctrl+click: clear it\n"
        "space pause/resume, N one round, P screenshot\n"
        "ctrl+S save image, Esc quit",
        std::min<size_t>(9, overlayList(*o.methods).size()));
  }
  if (!state.message.empty()) ImGui::TextWrapped("%s", state.message.c_str());
  ImGui::End();
}

namespace {

// The pixel drawn large: slices, B and C, the stored samples coloured by value (viridis),
// last round's candidates as rings (filled: kept); then the slices' and candidates' lists.
void drawSubpixel(const SubpixelInspection& sub) {
  const float side = std::min(ImGui::GetContentRegionAvail().x, 300.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + side, origin.y + side), IM_COL32(30, 30, 34, 255));
  const int S = std::max(1, sub.slicesPerSide);
  const float cell = side / float(S);
  for (int s = 0; s < S * S; ++s) {
    const ImVec2 a(origin.x + (s % S) * cell, origin.y + (s / S) * cell);
    const ImVec2 b(a.x + cell, a.y + cell);
    if (s == sub.sliceB) draw->AddRectFilled(a, b, IM_COL32(64, 140, 255, 70));
    if (s == sub.sliceC) draw->AddRectFilled(a, b, IM_COL32(255, 140, 25, 70));
    draw->AddRect(a, b, IM_COL32(150, 150, 150, 255));
    char label[48];
    const bool hasStats = size_t(s) < sub.slices.size();
    std::snprintf(label, sizeof label, "%s%d n=%u",
                  s == sub.sliceB   ? "B "
                  : s == sub.sliceC ? "C "
                                    : "",
                  s, hasStats ? sub.slices[size_t(s)].count : 0u);
    draw->AddText(ImVec2(a.x + 3, a.y + 2), IM_COL32(220, 220, 220, 255), label);
  }
  auto at = [&](float ox, float oy) { return ImVec2(origin.x + ox * side, origin.y + oy * side); };
  for (const InspectedSample& s : sub.samples)
    draw->AddCircleFilled(at(s.ox, s.oy), 4.0f, toU32(colormapViridis(s.value)));
  for (const InspectedCandidate& c : sub.candidates) {
    const ImU32 color = toU32(colormapViridis(c.value));
    draw->AddCircle(at(c.ox, c.oy), 7.0f, c.kept ? IM_COL32(255, 255, 255, 255) : color, 0,
                    c.kept ? 2.5f : 1.5f);
  }
  ImGui::Dummy(ImVec2(side, side));
  ImGui::Text("%zu samples, %zu candidates last round", sub.samples.size(), sub.candidates.size());
  if (ImGui::TreeNode("slices")) {
    for (size_t s = 0; s < sub.slices.size(); ++s)
      ImGui::Text("%zu: n %u, mean v %.3f, eq. 15 %.4f", s, sub.slices[s].count,
                  sub.slices[s].meanValue, sub.slices[s].fDivergence);
    ImGui::TreePop();
  }
  if (!sub.candidates.empty() && ImGui::TreeNode("candidates (eq. 16)")) {
    for (const InspectedCandidate& c : sub.candidates)
      ImGui::Text("slice %d%s v %.3f score %.3f%s", c.slice,
                  c.mirroredFrom >= 0 ? " (mirrored)" : "", c.value, c.score,
                  c.kept ? "  kept" : "");
    ImGui::TreePop();
  }
}

// The pixel's network along the input that matters most: the neighbours' samples it was
// fitted on (grey), the pixel's own (orange, never fitted on) and the network's curve (white).
void drawFit(const InspectedFit& fit) {
  ImGui::TextWrapped("network along %s (demodulated luminance)", fit.input.c_str());
  const float width = std::min(ImGui::GetContentRegionAvail().x, 300.0f), height = 140.0f;
  // The value axis spans the curve and the samples' 2nd to 98th percentiles, so that a few
  // bright outliers (indirect light) do not flatten the rest; those are drawn at the edge.
  std::vector<float> values;
  for (const glm::vec2& s : fit.samples) values.push_back(s.y);
  for (const glm::vec2& s : fit.own) values.push_back(s.y);
  std::erase_if(values, [](float v) { return !std::isfinite(v); });
  std::sort(values.begin(), values.end());
  float lo = INFINITY, hi = -INFINITY;
  if (!values.empty()) {
    lo = values[size_t(0.02 * double(values.size() - 1))];
    hi = values[size_t(0.98 * double(values.size() - 1))];
  }
  for (float v : fit.curve)
    if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo) || !std::isfinite(hi)) lo = 0.0f, hi = 1.0f;
  if (!(hi > lo)) hi = lo + 1.0f;
  const float pad = 0.05f * (hi - lo);
  lo -= pad, hi += pad;
  const float span = std::max(fit.hi - fit.lo, 1e-6f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  auto at = [&](float x, float y) {
    const float v = std::clamp((y - lo) / (hi - lo), 0.0f, 1.0f);
    return ImVec2(origin.x + (x - fit.lo) / span * width, origin.y + height - v * height);
  };
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + width, origin.y + height),
                      IM_COL32(30, 30, 34, 255));
  for (const glm::vec2& s : fit.samples)
    draw->AddCircleFilled(at(s.x, s.y), 2.0f, IM_COL32(150, 150, 150, 200));
  for (const glm::vec2& s : fit.own)
    draw->AddCircleFilled(at(s.x, s.y), 3.0f, IM_COL32(255, 150, 40, 255));
  for (size_t i = 1; i < fit.curve.size(); ++i) {
    const float step = span / float(fit.curve.size() - 1);
    draw->AddLine(at(fit.lo + step * float(i - 1), fit.curve[i - 1]),
                  at(fit.lo + step * float(i), fit.curve[i]), IM_COL32(255, 255, 255, 255), 2.0f);
  }
  ImGui::Dummy(ImVec2(width, height));
  ImGui::Text("%s %.2f .. %.2f; value %.3g .. %.3g", fit.input.c_str(), fit.lo, fit.hi, lo, hi);
}

}  // namespace

void drawInspector(const PanelState& state, const PanelActions& actions) {
  ImGui::SetNextWindowPos(ImVec2(ImGui::GetIO().DisplaySize.x - 330, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(320, 0), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.85f);
  bool open = true;
  if (!ImGui::Begin("Pixel inspector", &open)) {
    ImGui::End();
    return;
  }
  if (!open) actions.inspectPixel(-1, -1);
  const auto in = state.inspection;
  if (!in || !in->valid || in->x != state.view.inspectX || in->y != state.view.inspectY) {
    ImGui::Text("pixel (%d, %d): waiting for the round to finish", state.view.inspectX,
                state.view.inspectY);
    ImGui::End();
    return;
  }
  ImGui::Text("pixel (%d, %d), %s, after round %d", in->x, in->y, in->method.c_str(), in->round);
  ImGui::TextWrapped("%s", in->reason.c_str());
  ImGui::Text("kept %u, traced %u, +%u last round", in->kept, in->traced, in->addedLastRound);
  ImGui::Text("estimate %.4g %.4g %.4g", in->estimate.x, in->estimate.y, in->estimate.z);
  // The method's own values, one line each, as it formatted them.
  for (const InspectedValue& v : in->values) ImGui::TextWrapped("%s", v.line.c_str());
  if (in->fit) drawFit(*in->fit);
  if (!in->subpixel || (in->subpixel->samples.empty() && in->subpixel->candidates.empty())) {
    ImGui::End();  // the baselines store no samples
    return;
  }
  drawSubpixel(*in->subpixel);
  ImGui::End();
}

}  // namespace penumbra
