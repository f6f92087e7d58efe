#include "engine/scene/lights.h"

#include <algorithm>
#include <cmath>

namespace ivgi::scene {

std::vector<gpu::PunctualLight> worldLights(const Scene& scene, const Pose& pose) {
  std::vector<gpu::PunctualLight> out;
  for (size_t i = 0; i < scene.nodes.size(); ++i) {
    if (scene.nodes[i].light < 0) continue;
    const Light& l = scene.lights[scene.nodes[i].light];
    const glm::mat4& m = pose.world[i];
    glm::vec3 dir = -glm::vec3(m[2]);
    float len = glm::length(dir);
    dir = len > 0 ? dir / len : glm::vec3(0, 0, -1);
    float type = l.type == Light::Type::Directional ? gpu::kLightDirectional
                 : l.type == Light::Type::Point     ? gpu::kLightPoint
                                                    : gpu::kLightSpot;
    out.push_back({glm::vec4(glm::vec3(m[3]), type), glm::vec4(dir, l.range), glm::vec4(l.color * l.intensity, 0.0f),
                   glm::vec4(std::cos(l.outerCone), std::cos(l.innerCone), 0.0f, 0.0f)});
  }
  return out;
}

uint32_t punctualLightCount(const Scene& scene) {
  return uint32_t(std::count_if(scene.nodes.begin(), scene.nodes.end(), [](const Node& n) { return n.light >= 0; }));
}

}  // namespace ivgi::scene
