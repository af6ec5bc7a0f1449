#include "sweep/sim/scene.h"

#include <cmath>

namespace sweep::sim {

int Scene::frame_count() const {
  return static_cast<int>(std::floor(duration * fps + 1e-9)) + 1;
}

}  // namespace sweep::sim
