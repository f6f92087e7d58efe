#pragma once
// GPU timings of a run of animation frames, as bench and the equal-error comparison take them.
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/cli/timeline.h"
#include "engine/gi/frame_renderer.h"

namespace ivgi::cli {

struct FrameTimes {
  std::map<std::string, std::vector<double>> perPass;        // ms per measured frame, and "total"
  std::vector<std::string> order;                            // passes in the order they ran
  nlohmann::json frames = nlohmann::json::array();           // per frame: number, gpuMs per pass, totalGpuMs, solver
  std::map<std::string, std::vector<double>> solverFigures;  // per measured frame, by name (e.g. bounces)
  // With FrameRenderer::timePrograms(): per program (shader), ms and dispatches per measured frame
  // (0 where it did not run).
  std::map<std::string, std::vector<double>> perProgram, programDispatches;
};

// Renders `warmup` + `count` frames of the animation in memory (wrapping around its end) and keeps
// the GPU times of the last `count`. Static geometry relinks only in the first frame.
FrameTimes timeFrames(gi::FrameRenderer& renderer, const scene::Scene& scene, const scene::Geometry& geometry,
                      const Timeline& timeline, const FrameCamera& camera, double fps, int warmup, int count);

}  // namespace ivgi::cli
