// The viewer's Dear ImGui windows, the panel and the pixel inspector, as free functions over
// an explicit interface: the state they show and edit (PanelState) and the few actions they
// trigger on the viewer (PanelActions). Call them between ImGui::NewFrame and ImGui::Render.
#pragma once

#include "methods/session.h"
#include "viewer/app/view_state.h"

#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace penumbra {

struct PanelState {
  ViewOptions& options;    // edited: method, parameters, display, overlay blend
  ViewState& view;         // edited: the save fields; read: zoom, cursor, inspected pixel
  RenderSession& session;  // pause, resume, one round, its state
  // The viewer's own pointers, read as they change (a restart replaces the snapshot).
  const std::shared_ptr<const Snapshot>& snapshot;           // null before the first picture
  const std::shared_ptr<const PixelInspection>& inspection;  // the latest, may be null
  const OverlayImage& overlay;                               // the overlay over the image
  const std::vector<std::pair<double, double>>& mseHistory;  // (kept spp, MSE)
  double firstPictureSeconds;  // restart to first picture, the last restart (-1: none)
  const FrameStats& frameStats;
  const std::string& configError;  // why the parameters cannot start
  std::string& message;            // the last message, shown at the panel's foot
};

struct PanelActions {
  std::function<void()> restart;  // with the current camera and parameters
  std::function<void(MapId)> setOverlay;
  std::function<void()> shownImageChanged;                   // raw/reconstructed toggled
  std::function<std::string(const std::string&)> saveImage;  // returns a message
  std::function<void(const std::string&)> requestScreenshot;
  std::function<void(int, int)> inspectPixel;                  // (-1, -1): none
  std::function<void(const std::string&)> openScene;           // the message says how it went
  std::function<void(RenderRegion)> setRegion;                 // an empty region renders everything
  std::function<void(const EnvironmentEdit&)> setEnvironment;  // the message says how it went
};

// The panel's controls of the run and the method, as the tables describe them: the run shape's
// settings the viewer takes (runShapeParams() entries with kViewCommand), and the chosen
// method's parameters by group, each group a tree node of the Method section.
struct ParamSection {
  std::string title;
  std::vector<const MethodParam*> params;
};
std::vector<const Param<RunShape>*> runWidgets();
std::vector<ParamSection> methodSections(const ViewOptions& options);

void drawPanel(const PanelState& state, const PanelActions& actions);
// Only while a pixel is inspected (view.inspectX >= 0).
void drawInspector(const PanelState& state, const PanelActions& actions);

}  // namespace penumbra
