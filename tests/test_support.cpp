#include "tests/test_support.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <numbers>
#include <sstream>

#include <OpenImageIO/imagebuf.h>

#include "engine/cli/app.h"
#include "engine/scene/gltf.h"
#include "scenes/builtin.h"
#include "scenes/gltf_builder.h"

namespace ivgi::test {

namespace {

std::unique_ptr<vk::Context>& context() {
  static std::unique_ptr<vk::Context> ctx;
  return ctx;
}

class ValidationGuard : public ::testing::Environment {
 public:
  void TearDown() override {
    if (context()) {
      EXPECT_EQ(context()->validationErrors(), 0u) << "Vulkan validation errors were reported";
    }
    context().reset();
  }
};
const auto* const kGuard = ::testing::AddGlobalTestEnvironment(new ValidationGuard);

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

vk::Context& gpu() {
  if (!context()) context() = std::make_unique<vk::Context>(vk::ContextOptions{.validation = true});
  return *context();
}

std::vector<std::string> Run::errLines() const {
  std::vector<std::string> lines;
  std::stringstream ss(err);
  for (std::string line; std::getline(ss, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

namespace {

// The whole of what `file` holds.
std::string readAll(std::FILE* file) {
  std::string text;
  std::rewind(file);
  char chunk[4096];
  for (size_t n; (n = std::fread(chunk, 1, sizeof chunk, file)) > 0;) text.append(chunk, n);
  return text;
}

// Runs the command line in this process on its device, its stdout and stderr caught in files.
Run runHere(const std::vector<std::string>& args) {
  vk::Context& device = gpu();
  std::vector<std::string> all = {IVGI_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::fflush(stdout), std::fflush(stderr);
  std::FILE *out = std::tmpfile(), *err = std::tmpfile();
  const int keptOut = dup(STDOUT_FILENO), keptErr = dup(STDERR_FILENO);
  dup2(fileno(out), STDOUT_FILENO), dup2(fileno(err), STDERR_FILENO);
  Run r;
  r.status = cli::run(all, &device);
  std::fflush(stdout), std::fflush(stderr);
  dup2(keptOut, STDOUT_FILENO), dup2(keptErr, STDERR_FILENO);
  close(keptOut), close(keptErr);
  r.out = readAll(out), r.err = readAll(err);
  std::fclose(out), std::fclose(err);
  return r;
}

}  // namespace

Run runIvgi(const std::vector<std::string>& args, const std::map<std::string, std::string>& env) {
  if (env.empty() && std::find(args.begin(), args.end(), "--device") == args.end()) return runHere(args);
  return runIvgiProcess(args, env);
}

Run runIvgiProcess(const std::vector<std::string>& args, const std::map<std::string, std::string>& env) {
  static int counter = 0;
  auto dir = std::filesystem::temp_directory_path() /
             ("ivgi-run-" + std::to_string(getpid()) + "-" + std::to_string(counter++));
  std::filesystem::create_directories(dir);
  std::string cmd = "env IVGI_VALIDATION=1";
  for (const auto& [k, v] : env) cmd += " " + k + "=" + quote(v);
  cmd += " " + quote(IVGI_BINARY);
  for (const auto& a : args) cmd += " " + quote(a);
  cmd += " </dev/null >" + quote((dir / "out").string()) + " 2>" + quote((dir / "err").string());
  int raw = std::system(cmd.c_str());
  Run r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : 128 + WTERMSIG(raw);
  r.out = slurp(dir / "out");
  r.err = slurp(dir / "err");
  std::filesystem::remove_all(dir);
  return r;
}

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::optional<std::filesystem::path> sharedGltfDir() {
  auto p = std::filesystem::path(IVGI_SOURCE_DIR) / ".." / "shared" / "data" / "gltf";
  if (std::filesystem::is_directory(p)) return std::filesystem::canonical(p);
  return std::nullopt;
}

std::vector<float> channelOf(const std::filesystem::path& exr, const std::string& name) {
  OIIO_NAMESPACE::ImageBuf buf(exr.string());
  std::vector<float> values;
  if (!buf.read(0, 0, true, OIIO_NAMESPACE::TypeDesc::FLOAT) || buf.spec().channelindex(name) < 0) return values;
  const size_t c = size_t(buf.spec().channelindex(name)), channels = size_t(buf.spec().nchannels);
  const float* p = static_cast<const float*>(buf.localpixels());
  for (size_t i = 0; i < size_t(buf.spec().image_pixels()); ++i) values.push_back(p[i * channels + c]);
  return values;
}

double meanOf(const image::RgbImage& im, int channel) {
  double sum = 0;
  for (const glm::vec3& p : im.pixels) sum += p[channel];
  return im.pixels.empty() ? 0.0 : sum / double(im.pixels.size());
}

std::filesystem::path assimpGltfDir() { return "/usr/share/assimp/models/glTF2"; }

gi::FrameRenderer ivRenderer(const scene::Geometry& geometry, gi::ImageSettings image, gi::IvSetup setup,
                             vk::Context& ctx) {
  return gi::FrameRenderer(ctx, geometry, image, std::make_unique<gi::IvSolver>(ctx, geometry, std::move(setup)));
}

const gi::IvSolver& ivSolver(const gi::FrameRenderer& renderer) {
  return dynamic_cast<const gi::IvSolver&>(*renderer.solver());
}

double cornellLightIrradiance(glm::dvec3 p, glm::dvec3 n, int k) {
  const scenes::CornellLight& l = scenes::kCornellLight;
  const double x0 = 1e-3 * l.x0, x1 = 1e-3 * l.x1, z0 = 1e-3 * l.z0, z1 = 1e-3 * l.z1, h = 1e-3 * l.height;
  double e = 0;
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) {
      glm::dvec3 d = glm::dvec3(x0 + (i + 0.5) * (x1 - x0) / k, h, z0 + (j + 0.5) * (z1 - z0) / k) - p;
      double d2 = glm::dot(d, d), cosR = glm::dot(n, d) / std::sqrt(d2), cosL = d.y / std::sqrt(d2);
      if (cosR > 0) e += l.radiance[0] * cosR * cosL / d2 * (x1 - x0) * (z1 - z0) / (k * k);
    }
  return e;
}

DirectLightErrors emptyRoomDirectLight(const std::vector<scene::Surfel>& surfels,
                                       const std::vector<glm::vec4>& emission,
                                       const std::function<double(size_t)>& irradianceOf) {
  std::vector<double> exact(surfels.size(), 0.0);
  double brightest = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    if (emission[i].x > 0.0f || surfels[i].normal.y < -0.9f) continue;  // the lamp, the ceiling
    exact[i] = cornellLightIrradiance(glm::dvec3(surfels[i].positionArea), glm::dvec3(surfels[i].normal), 48);
    brightest = std::max(brightest, exact[i]);
  }
  DirectLightErrors e;
  double got = 0, expected = 0;
  for (size_t i = 0; i < surfels.size(); ++i) {
    if (exact[i] < 0.05 * brightest) continue;  // grazing: a few bins' worth of light
    const double value = irradianceOf(i), error = std::abs(value - exact[i]) / exact[i];
    e.mean += error, e.worst = std::max(e.worst, error), ++e.counted;
    got += surfels[i].positionArea.w * value, expected += surfels[i].positionArea.w * exact[i];
  }
  e.mean /= std::max(e.counted, 1);
  e.total = got / std::max(expected, 1e-30);
  return e;
}

tinygltf::Model sunOverABox() {
  scenes::GltfBuilder b;
  const int grey = b.material("grey", glm::vec3(0.6f));
  scenes::MeshData floor, box;
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 8, 8, {0, 1, 0});
  scenes::addBox(box, {0.0f, 0.25f, 0.0f}, glm::vec3(0.25f), 2);
  b.node("floor", b.mesh("floor", {{floor, grey}}));
  b.node("box", b.mesh("box", {{box, grey}}));
  b.light("sun", "directional", 2.0f, {0, 2, 0}, glm::angleAxis(-1.2f, glm::vec3(1, 0, 0)));
  b.camera("down", 1.2f, 0.01f, {0, 1.5f, 0.5f}, glm::angleAxis(-1.3f, glm::vec3(1, 0, 0)));
  return b.finish();
}

namespace {

tinygltf::Model underRoot(tinygltf::Model model, tinygltf::Node root) {
  root.children = model.scenes[0].nodes;
  model.nodes.push_back(root);
  model.scenes[0].nodes = {int(model.nodes.size() - 1)};
  return model;
}

}  // namespace

tinygltf::Model scaled(tinygltf::Model model, float factor) {
  tinygltf::Node root;
  root.name = "scale";
  root.scale = {factor, factor, factor};
  return underRoot(std::move(model), root);
}

tinygltf::Model turned(tinygltf::Model model, float degrees, glm::vec3 axis) {
  tinygltf::Node root;
  root.name = "turn";
  const glm::quat q = glm::angleAxis(glm::radians(degrees), glm::normalize(axis));
  root.rotation = {q.x, q.y, q.z, q.w};
  return underRoot(std::move(model), root);
}

std::filesystem::path scratchDir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string test = info ? std::string(info->test_suite_name()) + "." + info->name() : "none";
  auto dir =
      std::filesystem::temp_directory_path() / "ivgi-tests" / (test + "-" + name + "-" + std::to_string(getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::filesystem::path renderExr(const std::string& name, const std::vector<std::string>& args) {
  auto dir = scratchDir(name);
  std::vector<std::string> all = {"render", "--format", "exr", "--out", (dir / "f").string()};
  if (std::find(args.begin(), args.end(), "--frames") == args.end()) all.insert(all.end(), {"--frames", "0"});
  all.insert(all.end(), args.begin(), args.end());
  auto r = runIvgi(all);
  EXPECT_EQ(r.status, 0) << r.err;
  return dir / "f_0000.exr";
}

std::filesystem::path renderModelExr(const std::string& name, const tinygltf::Model& model,
                                     const std::vector<std::string>& args) {
  const auto file = scratchDir(name + "-scene") / (name + ".gltf");
  scenes::writeModel(model, file.string());
  std::vector<std::string> all = {file.string()};
  all.insert(all.end(), args.begin(), args.end());
  return renderExr(name, all);
}

void expectRefusedNaming(const std::string& name, const std::vector<std::string>& args,
                         const std::vector<std::string>& named) {
  const auto dir = scratchDir(name);
  std::vector<std::string> all = {"render", "--out", (dir / "f").string()};
  all.insert(all.end(), args.begin(), args.end());
  const Run r = runIvgi(all);
  EXPECT_NE(r.status, 0);
  ASSERT_EQ(r.errLines().size(), 1u) << r.err;
  for (const std::string& word : named) EXPECT_NE(r.err.find(word), std::string::npos) << word << ": " << r.err;
  EXPECT_TRUE(std::filesystem::is_empty(dir)) << "nothing written";
}

void expectTheSameFromHostMemory(const std::string& name, const std::vector<std::string>& args,
                                 const std::string& mebibytes, const std::vector<int>& frames) {
  const auto dir = scratchDir(name);
  auto render = [&](const std::string& out, const std::vector<std::string>& extra) {
    std::vector<std::string> all = {"render", "--format", "exr", "--out", (dir / out).string()};
    all.insert(all.end(), args.begin(), args.end());
    all.insert(all.end(), extra.begin(), extra.end());
    return runIvgi(all);
  };
  const Run device = render("device", {}), host = render("host", {"--max-memory", mebibytes});
  ASSERT_EQ(device.status, 0) << device.err;
  ASSERT_EQ(host.status, 0) << host.err;
  EXPECT_EQ(device.err.find("host memory"), std::string::npos) << device.err;
  const auto lines = host.errLines();
  EXPECT_EQ(std::count_if(lines.begin(), lines.end(),
                          [](const std::string& line) { return line.find("host memory") != std::string::npos; }),
            1)
      << host.err;
  EXPECT_NE(host.err.find("--max-memory of " + mebibytes + " MiB"), std::string::npos) << host.err;
  for (int frame : frames) {
    char suffix[16];
    std::snprintf(suffix, sizeof suffix, "_%04d.exr", frame);
    for (const char* channel : {"R", "G", "B"})
      EXPECT_EQ(channelOf(dir / ("host" + std::string(suffix)), channel),
                channelOf(dir / ("device" + std::string(suffix)), channel))
          << suffix << " " << channel;
  }
}

std::string bigEndian(uint32_t v, int bytes) {
  std::string s;
  for (int k = bytes - 1; k >= 0; --k) s += char(v >> (8 * k) & 255);
  return s;
}

int addTexture(tinygltf::Model& model, int width, int height, std::vector<uint8_t> rgba, int sampler) {
  tinygltf::Image image;
  image.width = width, image.height = height, image.component = 4, image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.image = std::move(rgba);
  image.mimeType = "image/png";
  model.images.push_back(image);
  tinygltf::Texture texture;
  texture.source = int(model.images.size() - 1), texture.sampler = sampler;
  model.textures.push_back(texture);
  return int(model.textures.size() - 1);
}

int addGreyTexture(tinygltf::Model& model, int side, const std::function<uint8_t(int x, int y)>& grey, int sampler) {
  std::vector<uint8_t> rgba;
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x) {
      const uint8_t v = grey(x, y);
      rgba.insert(rgba.end(), {v, v, v, 255});
    }
  return addTexture(model, side, side, std::move(rgba), sampler);
}

scenes::MeshData uvSphere(int rings, bool bumps) {
  scenes::MeshData m;
  const int segments = 2 * rings;
  for (int i = 0; i <= rings; ++i)
    for (int j = 0; j <= segments; ++j) {
      const double theta = std::numbers::pi * i / rings, phi = 2.0 * std::numbers::pi * j / segments;
      const double r = bumps ? 1.0 + 0.15 * std::sin(5.0 * theta) * std::sin(5.0 * phi) : 1.0;
      m.positions.push_back(
          glm::vec3(r * std::sin(theta) * std::cos(phi), r * std::cos(theta), r * std::sin(theta) * std::sin(phi)));
    }
  const uint32_t w = uint32_t(segments + 1);
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint32_t v = uint32_t(i) * w + uint32_t(j);
      if (i > 0) m.indices.insert(m.indices.end(), {v, v + 1, v + w});
      if (i + 1 < rings) m.indices.insert(m.indices.end(), {v + 1, v + w + 1, v + w});
    }
  return m;
}

scenes::MeshData ball(int rings, float radius, glm::vec3 centre) {
  scenes::MeshData m = uvSphere(rings);
  for (glm::vec3& p : m.positions) p = radius * p + centre;
  return m;
}

tinygltf::Model ballOnFloor(const scenes::MeshData& ball, glm::vec3 albedo, int cells, float intensity,
                            glm::vec3 lamp) {
  scenes::GltfBuilder b;
  const int grey = b.material("grey", glm::vec3(0.5f)), own = b.material("ball", albedo);
  scenes::MeshData floor;
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, cells, cells, {0, 1, 0});
  b.node("floor", b.mesh("floor", {{floor, grey}}));
  b.node("ball", b.mesh("ball", {{ball, own}}));
  b.light("lamp", "point", intensity, lamp);
  return b.finish();
}

AtRest atRest(const tinygltf::Model& model, const std::string& name) {
  AtRest r{.scene = scene::sceneFromModel(model, name)};
  r.geometry = scene::buildGeometry(r.scene);
  r.pose = scene::evaluatePose(r.scene, -1, 0.0f);
  r.inputs = r.geometry.frameInputs(r.scene, r.pose);
  return r;
}

scene::CameraView framing(const scene::Geometry& geometry, const scene::FrameInputs& inputs) {
  return scene::framingCamera(scene::worldBounds(scene::animateOnHost(geometry, inputs)), 1.0f);
}

}  // namespace ivgi::test
