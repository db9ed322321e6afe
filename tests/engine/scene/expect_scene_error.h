// The scene-reading tests' shared check: a loader call must throw a SceneError whose message
// holds every fragment (the file, the line or element, the field, the reason).
#pragma once

#include "scene/scene.h"

#include <gtest/gtest.h>

#include <functional>
#include <initializer_list>
#include <string>

namespace penumbra::test {

inline void expectSceneError(const std::function<void()>& load,
                             std::initializer_list<std::string> fragments) {
  try {
    load();
    ADD_FAILURE() << "no SceneError thrown";
  } catch (const SceneError& error) {
    const std::string message = error.what();
    for (const std::string& fragment : fragments)
      EXPECT_NE(message.find(fragment), std::string::npos)
          << "'" << fragment << "' not in: " << message;
  }
}

}  // namespace penumbra::test
