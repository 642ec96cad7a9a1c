// The message a scene's text is refused with, "no error" when it loads (tests of the scene readers).
#pragma once
#include <string>

#include <simreel/error.hpp>
#include "app/scene/scene.hpp"

namespace simreel::test {

inline std::string scene_error(const std::string& text, const std::string& path) {
  try {
    load_scene_text(text, path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

}  // namespace simreel::test
