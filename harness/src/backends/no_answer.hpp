// no_answer.hpp: what every backend says when a scene takes longer than
// BackendOptions::timeout_seconds, so that a GL worker that is killed and a reference render
// that is stopped report the same status (RenderStatus::Timeout) in the same words.
#pragma once

#include <string>

#include "harness/scene.hpp"

namespace harness {

// The scene as a message names it: its file, else its name.
inline std::string scene_label(const Scene& scene) {
    if (!scene.path.empty()) return scene.path.string();
    if (!scene.file.name.empty()) return "scene " + scene.file.name;
    return "an unnamed scene";
}

// "<who> gave no answer within <seconds> s for <label> (<how>)".
inline std::string no_answer_message(const std::string& who, double seconds,
                                     const std::string& label, const std::string& how) {
    return who + " gave no answer within " + std::to_string(seconds) + " s for " + label + " (" +
           how + ")";
}

}  // namespace harness
