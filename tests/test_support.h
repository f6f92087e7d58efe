#pragma once
// Helpers shared by the tests: one Vulkan context per test process (validation on), running ivgi's
// command line, the real glTF assets, scratch folders.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "engine/gi/frame_renderer.h"
#include "engine/gi/iv/solver.h"
#include "engine/image/metrics.h"
#include "engine/vk/context.h"
#include "scenes/gltf_builder.h"

namespace tinygltf {
class Model;
}

namespace ivgi::test {

// The process's Vulkan context, with validation layers on; the test environment fails any test
// process whose validation layer reported an error.
vk::Context& gpu();
// While it lives, every buffer made on gpu() holds `word` first (vk::Context::fillFreshMemory).
struct FreshMemoryFill {
  explicit FreshMemoryFill(uint32_t word) { gpu().fillFreshMemory(word); }
  ~FreshMemoryFill() { gpu().fillFreshMemory(std::nullopt); }
  FreshMemoryFill(const FreshMemoryFill&) = delete;
  FreshMemoryFill& operator=(const FreshMemoryFill&) = delete;
};

struct Run {
  int status = -1;
  std::string out, err;
  std::vector<std::string> errLines() const;
};
// Runs the command line `ivgi ARGS`, validation on: in this process on gpu() (cli::run), or, where
// `env` sets variables or the args name a --device, as build/ivgi in a process of its own.
Run runIvgi(const std::vector<std::string>& args, const std::map<std::string, std::string>& env = {});
// Runs build/ivgi with `args` (validation on) in a process of its own and waits.
Run runIvgiProcess(const std::vector<std::string>& args, const std::map<std::string, std::string>& env = {});

// A file's bytes (empty where it cannot be read).
std::string readFile(const std::filesystem::path& path);

// ../shared/data/gltf beside the checkout, when present.
std::optional<std::filesystem::path> sharedGltfDir();
// Debian's assimp-testmodels glTF 2.0 folder (installed by ci/install-deps.sh).
std::filesystem::path assimpGltfDir();
// A renderer of `geometry` lit by an iv solver made from `setup`, on `ctx` (the test process's).
gi::FrameRenderer ivRenderer(const scene::Geometry& geometry, gi::ImageSettings image, gi::IvSetup setup,
                             vk::Context& ctx = gpu());
// The iv solver of a renderer made by ivRenderer().
const gi::IvSolver& ivSolver(const gi::FrameRenderer& renderer);

// Direct irradiance (red) from the built-in Cornell box's light at p with unit normal n, by k×k
// midpoint quadrature of L·cos θ·cos θ'/d² over its rectangle.
double cornellLightIrradiance(glm::dvec3 p, glm::dvec3 n, int k);

// The direct light of the empty Cornell room's lamp at each surfel that sees it well (walls and floor;
// not the lamp, nor the ceiling level with it, nor where it comes grazing, under 5 % of the
// brightest) against cornellLightIrradiance(): how many, and the mean and worst relative error of
// irradianceOf(i), a solver's irradiance (red) at surfel i; and the light they receive in all (Σ area ·
// irradiance) over the exact.
struct DirectLightErrors {
  int counted = 0;
  double mean = 0, worst = 0, total = 0;
};
DirectLightErrors emptyRoomDirectLight(const std::vector<scene::Surfel>& surfels,
                                       const std::vector<glm::vec4>& emission,
                                       const std::function<double(size_t)>& irradianceOf);

// `model` under a new root node that scales its scenes' roots by `factor`.
tinygltf::Model scaled(tinygltf::Model model, float factor);
// `model` under a new root node that turns its scenes' roots, cameras among them, by `degrees`
// about `axis`: the same scene seen the same way, askew to the world's axes.
tinygltf::Model turned(tinygltf::Model model, float degrees, glm::vec3 axis);
// A sun over a floor with a box on it (two objects), and a camera looking down at them.
tinygltf::Model sunOverABox();

// One channel of an EXR file ("R", "albedo.G", "N.Y", …), row-major; empty if the file or the
// channel cannot be read.
std::vector<float> channelOf(const std::filesystem::path& exr, const std::string& name);

// The mean of one channel (0 red, 1 green, 2 blue) over an image's pixels; 0 for an empty image.
double meanOf(const image::RgbImage& im, int channel = 0);

// `v`'s low `bytes` bytes, most significant first (file headers written by hand).
std::string bigEndian(uint32_t v, int bytes = 4);

// Adds to `model` an 8-bit RGBA image `width` × `height` of `rgba` (rows from the top) and a texture of
// it through sampler `sampler` (-1: glTF's default); its texture index.
int addTexture(tinygltf::Model& model, int width, int height, std::vector<uint8_t> rgba, int sampler = -1);

// Adds to `model` a grey image `side` texels square, each texel's sRGB byte grey(x, y) (y down),
// and a texture of it through sampler `sampler` (-1: glTF's default); its texture index.
int addGreyTexture(tinygltf::Model& model, int side, const std::function<uint8_t(int x, int y)>& grey,
                   int sampler = -1);

// A fresh, empty folder for one test.
std::filesystem::path scratchDir(const std::string& name);

// Renders `args` (frame 0 unless they name --frames) as EXR into scratchDir(name) and returns the
// path of frame 0's file; a failed run fails the test.
std::filesystem::path renderExr(const std::string& name, const std::vector<std::string>& args);
// `model` written to a scratch .gltf and rendered as renderExr() renders a file, `args` after it.
std::filesystem::path renderModelExr(const std::string& name, const tinygltf::Model& model,
                                     const std::vector<std::string>& args);

// Renders `args` (a scene and its settings) into scratchDir(name): the run must fail with one line
// on stderr that names each of `named`, and write nothing.
void expectRefusedNaming(const std::string& name, const std::vector<std::string>& args,
                         const std::vector<std::string>& named);

// Renders `args` (a scene, its settings and its --frames) as EXR into scratchDir(name) twice: as
// the device holds it, then with --max-memory `mebibytes`. The second run must say once, on
// stderr, that it holds links or tables in host memory, and each of `frames` must equal the first
// run's in every colour channel, bit for bit.
void expectTheSameFromHostMemory(const std::string& name, const std::vector<std::string>& args,
                                 const std::string& mebibytes, const std::vector<int>& frames);

// A sphere of radius 1 about the origin, `rings` × 2·`rings` quads (the poles' as triangles), its
// seam's vertices doubled as a texture's seam doubles them; with `bumps`, its radius 1 + 0.15 ·
// sin(5θ)·sin(5φ), hills and hollows.
scenes::MeshData uvSphere(int rings, bool bumps = false);
// uvSphere(rings) of radius `radius` about `centre`.
scenes::MeshData ball(int rings, float radius, glm::vec3 centre);
// `ball` (of albedo `albedo`, its node named "ball") over a grey (0.5) 2 m floor of cells × cells at
// y = 0, under a point lamp of `intensity` at `lamp`.
tinygltf::Model ballOnFloor(const scenes::MeshData& ball, glm::vec3 albedo, int cells, float intensity, glm::vec3 lamp);

// A model's scene at rest (no animation, time 0): its geometry as modelled, the pose and its inputs.
struct AtRest {
  scene::Scene scene;
  scene::Geometry geometry;
  scene::Pose pose;
  scene::FrameInputs inputs;
};
AtRest atRest(const tinygltf::Model& model, const std::string& name);

// A camera (aspect 1) framing the geometry as `inputs` place it.
scene::CameraView framing(const scene::Geometry& geometry, const scene::FrameInputs& inputs);

}  // namespace ivgi::test
