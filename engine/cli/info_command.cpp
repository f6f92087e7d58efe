#include <algorithm>
#include <cstdio>

#include "engine/cli/commands.h"
#include "engine/gi/frame_renderer.h"
#include "engine/scene/animation.h"
#include "engine/scene/camera.h"
#include "engine/scene/geometry.h"
#include "engine/scene/lights.h"
#include "engine/vk/context.h"

namespace ivgi::cli {

namespace {

// Link counts are known only once the GPU has refined them: frame 0 solved on a tiny image.
void solveFrameZero(gi::FrameRenderer& renderer, const scene::Scene& s, const scene::Geometry& g) {
  const int animation = s.animations.empty() ? -1 : 0;
  auto pose = scene::evaluatePose(s, animation, s.animations.empty() ? 0.0f : s.animations[0].start);
  renderer.render(g.frameInputs(s, pose),
                  scene::framingCamera(scene::worldBounds(scene::animateOnHost(g, g.frameInputs(s, pose))), 1.0f),
                  scene::worldLights(s, pose));
}

}  // namespace

int runInfo(const InfoOptions& o) {
  scene::Scene s = loadScene(o.source);
  scene::Geometry g = scene::buildGeometry(s, 0, buildProgress(), o.source.limits, openSpaceOf(o.solver, s));
  const SolverOptions solver = withSceneLight(o.solver, s, g);
  size_t primitives = 0, morphTargets = 0, colored = 0;
  for (const auto& m : s.meshes) {
    primitives += m.primitives.size();
    for (const auto& p : m.primitives) morphTargets += p.targets.size(), colored += p.colors.empty() ? 0 : 1;
  }
  auto world = scene::animateOnHost(g, g.frameInputs(s, scene::evaluatePose(s, -1, 0.0f)));
  scene::Bounds b = scene::worldBounds(world);

  std::printf("scene        %s\n", s.source.c_str());
  const size_t drawn = g.instances.size() - g.backInstances;
  std::printf("meshes       %zu (%zu primitives, %zu drawn instances, %zu morph targets)\n", s.meshes.size(),
              primitives, drawn, morphTargets);
  std::printf("vertices     %zu\n", g.vertices.size());
  std::printf("triangles    %zu (%u degenerate, excluded)\n", g.triangles.size(), g.degenerateTriangles);
  std::printf("surfels      %zu\n", g.surfels.size());
  if (g.backInstances > 0)
    std::printf(
        "backs        %u of the triangles and %u of the surfels: the exposed backs of %u open double-sided "
        "instance%s\n",
        g.backTriangles, g.backSurfels, g.backInstances, g.backInstances == 1 ? "" : "s");
  const std::vector<bool> closed = scene::closedInstances(g);
  std::printf("closed       %zu of %zu drawn instances enclose a volume\n",
              size_t(std::count(closed.begin(), closed.begin() + std::ptrdiff_t(drawn), true)), drawn);
  if (sampledTessellation(solver) > 0) {
    const scene::Geometry sampled = renderableGeometry(s, solver, o.source.limits);
    std::printf("tessellated  %zu triangles, %zu surfels (%s, --tessellate %u)\n", sampled.triangles.size(),
                sampled.surfels.size(), solver.method.c_str(), solver.tessellation);
  }
  auto materials = [&](auto has) { return size_t(std::count_if(s.materials.begin(), s.materials.end(), has)); };
  const size_t normalMapped = materials([](const scene::Material&m) { return m.normalTexture >= 0; }),
               cut = materials([](const scene::Material&m) { return m.alphaCutoff >= 0.0f; }),
               blended = materials([](const scene::Material&m) { return m.alphaCutoff == gpu::kAlphaBlended; });
  std::printf(
      "materials    %zu (%zu with a normal texture, %zu cut by alphaMode MASK, %zu blended), textures %zu, vertex "
      "colours in %zu of %zu primitives\n",
      s.materials.size(), normalMapped, cut, blended, s.textures.size(), colored, primitives);
  std::printf("nodes        %zu, skins %zu\n", s.nodes.size(), s.skins.size());
  std::printf("animations   %zu\n", s.animations.size());
  for (size_t i = 0; i < s.animations.size(); ++i) {
    const auto& a = s.animations[i];
    std::printf("  [%zu] %-20s %.3f s (%.3f to %.3f), %zu channels\n", i, a.name.c_str(), a.end - a.start, a.start,
                a.end, a.channels.size());
  }
  auto cams = s.cameraNodes();
  std::printf("cameras      %zu%s\n", cams.size(), cams.empty() ? " (a default camera frames the bounds)" : "");
  for (size_t i = 0; i < cams.size(); ++i) {
    const auto& c = s.cameras[s.nodes[cams[i]].camera];
    std::printf(c.orthographic ? "  [%zu] %-20s orthographic, ymag %g, node '%s'\n"
                               : "  [%zu] %-20s yfov %.2f deg, node '%s'\n",
                i, c.name.c_str(), c.orthographic ? c.ymag : c.yfov * 57.2957795f, s.nodes[cams[i]].name.c_str());
  }
  std::printf("lights       %zu\n", s.lights.size());
  const char* kinds[] = {"directional", "point", "spot"};
  for (size_t i = 0; i < s.lights.size(); ++i)
    std::printf("  [%zu] %-20s %s, intensity %g\n", i, s.lights[i].name.c_str(), kinds[int(s.lights[i].type)],
                s.lights[i].intensity);
  if (b.empty())
    std::printf("bounds       empty\n");
  else
    std::printf("bounds       (%.4g, %.4g, %.4g) to (%.4g, %.4g, %.4g), rest pose\n", b.min.x, b.min.y, b.min.z,
                b.max.x, b.max.y, b.max.z);
  std::printf("warnings     %zu\n", s.warnings.size());
  for (const auto& w : s.warnings) std::printf("  %s\n", w.c_str());
  if (o.memory && solver.method == "ar") {
    // The tables follow from the counts alone; the links are known once the GPU made them.
    const scene::Geometry sampled = renderableGeometry(s, solver, o.source.limits);
    const gi::Hierarchy h = gi::restPoseHierarchy(s, sampled);
    const gi::ArSettings ar = arSettings(solver);
    const bool chained = ar.chained();
    const uint64_t tables = gi::ArSolver::tableBytes(h.nodes.size(), sampled.surfels.size(), ar.dirs, chained);
    std::printf(
        "ar tables    dirs 6x%ux%u: %zu nodes and %zu surfels x %u bins x (gathered, intensity; incident%s) "
        "x RGBA32F = %.1f MiB\n",
        ar.dirs, ar.dirs, h.nodes.size(), sampled.surfels.size(), 6 * ar.dirs * ar.dirs,
        chained ? ", the chain's start" : "", double(tables) / (1 << 20));
    const std::shared_ptr<vk::Context> device = openDevice(o.device);
    vk::Context& ctx = *device;
    gi::FrameRenderer renderer(ctx, sampled, {16, 16, 1},
                               makeSolver(solver, ctx, s, sampled, s.animations.empty() ? -1 : 0, &h));
    solveFrameZero(renderer, s, sampled);
    const gi::ArStats st = dynamic_cast<const gi::ArSolver&>(*renderer.solver()).stats();
    std::printf("ar solver    %u nodes in %u levels, %u links, %u iterations, %.1f MiB on %s\n", st.nodes, st.levels,
                st.links, st.iterations, double(st.bytes) / (1 << 20), ctx.info().name.c_str());
  }
  if (o.memory && solver.method == "iv") {
    const std::shared_ptr<vk::Context> device = openDevice(o.device);
    vk::Context& ctx = *device;
    g = renderableGeometry(s, solver, o.source.limits);
    // A 16×16 image reads few surfels: every surface is judged as if shown, the most a render needs.
    SolverOptions everySurface = solver;
    everySurface.iv.unseenTolerance = 1.0f;
    gi::FrameRenderer renderer(ctx, g, {16, 16, 1}, makeSolver(everySurface, ctx, s, g, s.animations.empty() ? -1 : 0));
    solveFrameZero(renderer, s, g);
    const auto& iv = dynamic_cast<const gi::IvSolver&>(*renderer.solver());
    const gi::IvStats st = iv.stats();
    std::printf(
        "iv solver    bins 6x%ux%u (%s memory), eps %g: %u nodes in %u levels, %u receivers (--receiver-tol %g), "
        "%u links, %u leaf links, %.1f MiB on %s\n",
        solver.iv.bins, solver.iv.bins, st.sharedBins ? "shared" : "global", solver.iv.epsilon, st.nodes, st.levels,
        st.receivers, *iv.settings().receiverTolerance, st.links, st.leafLinks, double(st.bytes) / (1 << 20),
        ctx.info().name.c_str());
  }
  return 0;
}

int runDevices() {
  auto devices = vk::Context::listDevices();
  for (const auto& d : devices)
    std::printf("[%u] %s (%s), driver %s %s, uuid %s%s%s\n", d.index, d.name.c_str(), d.type.c_str(),
                d.driverName.c_str(), d.driverInfo.c_str(), d.uuid.c_str(),
                d.missing.empty() ? "" : ", unsuitable: lacks ", d.missing.c_str());
  if (devices.empty()) std::printf("no Vulkan devices\n");
  return 0;
}

}  // namespace ivgi::cli
