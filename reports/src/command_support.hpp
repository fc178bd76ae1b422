// What the command implementations share and the public API does not offer.
#pragma once

#include "marchcheck/sdf/scene.hpp"

#include <string>
#include <vector>

namespace marchcheck::reports {

// Applies "--set KEY=VALUE" overrides; throws sdf::SceneError naming the option at fault.
void apply_sets(sdf::Scene& scene, const std::vector<std::string>& sets);

}  // namespace marchcheck::reports
