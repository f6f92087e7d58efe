// The ivgi command as users drive it: options, output files, sidecar, resume, interruption,
// progress, built-in scenes, device choice.
#include <gtest/gtest.h>

#include <OpenImageIO/imageio.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <nlohmann/json.hpp>
#include <thread>

#include "engine/cli/frame_writer.h"
#include "engine/cli/options.h"
#include "engine/cli/sidecar.h"
#include "scenes/gltf_builder.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

TEST(Options, FrameRanges) {
  EXPECT_EQ(cli::parseFrameRange("7").frames(), std::vector<int>{7});
  EXPECT_EQ(cli::parseFrameRange("0-3").frames(), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(cli::parseFrameRange("2-9:3").frames(), (std::vector<int>{2, 5, 8}));
  for (const char* bad : {"", "-1", "3-1", "1-4:0", "a-b", "1-2-3", "99999999999"})
    EXPECT_THROW(cli::parseFrameRange(bad), SettingsError) << bad;
}

TEST(Options, OutputPatterns) {
  cli::OutputPattern p("out/f_%04d.exr");
  EXPECT_EQ(p.path(12, "exr"), "out/f_0012.exr");
  EXPECT_EQ(p.path(12, "png"), "out/f_0012.png");
  EXPECT_EQ(p.sidecar(), "out/f.json");
  EXPECT_EQ(p.directory(), "out");
  EXPECT_EQ(cli::OutputPattern("shot%d_beauty").path(3, "png"), "shot3_beauty.png");
  EXPECT_EQ(cli::OutputPattern("render").path(3, "exr"), "render_0003.exr") << "no conversion: the number is appended";
  EXPECT_THROW(cli::OutputPattern("a%d%d"), SettingsError);
  uint32_t w, h;
  cli::parseSize("640x360", w, h);
  EXPECT_EQ(w, 640u);
  EXPECT_EQ(h, 360u);
  EXPECT_EQ(cli::parseFormats("png,exr,png"), (std::vector<std::string>{"png", "exr"}));
}

TEST(Render, WritesFramesAndASidecarWithPerPassTimes) {
  auto dir = test::scratchDir("out");
  auto r = test::runIvgi({"render", "--frames", "0-4:2", "--size", "64x48", "--out", (dir / "f_%03d").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* f : {"f_000.exr", "f_000.png", "f_002.exr", "f_002.png", "f_004.exr", "f_004.png"})
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  EXPECT_FALSE(fs::exists(dir / "f_001.exr"));
  std::ifstream in(dir / "f.json");
  auto j = nlohmann::json::parse(in);
  ASSERT_EQ(j["frames"].size(), 3u);
  for (const auto& frame : j["frames"]) {
    for (const char* pass : {"animate", "surfels", "raster", "resolve"}) {
      ASSERT_TRUE(frame["gpuMs"].contains(pass)) << pass;
      EXPECT_GT(frame["gpuMs"][pass].get<double>(), 0.0) << pass;
    }
    EXPECT_GT(frame["hostPeakMiB"].get<double>(), 10.0);  // the host's peak so far: never falls
  }
  EXPECT_GE(j["frames"][2]["hostPeakMiB"].get<double>(), j["frames"][0]["hostPeakMiB"].get<double>());
  EXPECT_EQ(j["frames"][2]["frame"], 4);
  EXPECT_NEAR(j["frames"][2]["time"].get<double>(), 4.0 / 24.0, 1e-12);
  EXPECT_FALSE(j["device"]["name"].get<std::string>().empty());
  EXPECT_FALSE(j["device"]["driver"].get<std::string>().empty());
  EXPECT_EQ(j["settings"]["width"], 64);
  EXPECT_GT(j["medianGpuMs"]["total"].get<double>(), 0.0);
  // The progress line reached 3/3 and, on a pipe, is plain lines.
  EXPECT_NE(r.err.find("render: frame 3/3 (100%)"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find('\r'), std::string::npos);
}

// --direct maps: the sidecar says where the direct light came from and times its pass.
TEST(Render, DirectLightFromMapsIsNamedAndTimed) {
  auto dir = test::scratchDir("out");
  auto r = test::runIvgi({"render", "--frames", "0", "--size", "32x24", "--direct", "maps", "--light-samples", "8",
                          "--shadow-map", "32", "--out", (dir / "f_%03d").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir / "f.json");
  auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["settings"]["direct"],
            (nlohmann::json{{"from", "maps"}, {"lightSamples", 8}, {"shadowMap", 32}, {"environmentDirections", 0}}));
  EXPECT_GT(j["frames"][0]["gpuMs"]["direct light"].get<double>(), 0.0);
}

// By default iv and ar take the direct light per pixel where the scene's emitters are a small part
// of it (the Cornell box's lamp), and leave it to the solver where they surround the receivers (the
// furnace, every wall emitting), which the sidecar names; pt traces its own.
TEST(Render, TheDefaultDirectLightSuitsTheScene) {
  auto directOf = [](const std::vector<std::string>& scene) {
    auto dir = test::scratchDir("out");
    std::vector<std::string> args = {"render"};
    args.insert(args.end(), scene.begin(), scene.end());
    args.insert(args.end(), {"--frames", "0", "--size", "16x12", "--out", (dir / "f_%03d").string()});
    auto r = test::runIvgi(args);
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / "f.json");
    return nlohmann::json::parse(in)["settings"]["direct"];
  };
  EXPECT_EQ(directOf({"cornell"})["from"], "pixels");
  EXPECT_EQ(directOf({"cornell", "--method", "ar"})["from"], "pixels");
  EXPECT_EQ(directOf({"furnace", "--cells", "4"})["from"], "bins");
  // A glowing sign of a fifth of the surface beside a lamp: to the pixels where the sign gives a
  // tenth of the light or less (the lamp's shadows gain there), else to the bins.
  auto signAndLamp = [](float signRadiance) {
    scenes::GltfBuilder b;
    scenes::MeshData floor, sign;
    scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 2, 2, {0, 1, 0});
    scenes::addQuad(sign, {-0.5f, 0.2f, -1}, {0.5f, 0.2f, -1}, {0.5f, 1.2f, -1}, {-0.5f, 1.2f, -1}, 1, 1, {0, 0.7f, 0});
    b.node("floor", b.mesh("floor", {{floor, b.material("floor", glm::vec3(0.5f))}}));
    b.node("sign", b.mesh("sign", {{sign, b.material("sign", glm::vec3(0.0f), glm::vec3(signRadiance))}}));
    b.light("lamp", "point", 100.0f, {0, 1.5f, 0});  // 4π·100 ≈ 1,257 against the sign's π·L·1 m²
    const std::filesystem::path file =
        test::scratchDir("sign") / ("sign_" + std::to_string(int(signRadiance)) + ".gltf");
    scenes::writeModel(b.finish(), file.string());
    return file.string();
  };
  EXPECT_EQ(directOf({signAndLamp(1.0f)})["from"], "pixels");
  EXPECT_EQ(directOf({signAndLamp(1000.0f)})["from"], "bins");
  // The environment through the solvers' bins unless asked for through the maps.
  EXPECT_EQ(directOf({"cornell", "--env", "1,1,1"})["environmentDirections"], 0);
  EXPECT_EQ(directOf({"cornell", "--env", "1,1,1", "--env-directions", "16"})["environmentDirections"], 16);
}

// What a file holds that ivgi ignores is said once by every command that renders it: bench and
// the sweep said nothing, so a benchmark of a file could leave out part of it unremarked.
TEST(Render, EveryCommandSaysWhatTheFileHoldsThatIsIgnored) {
  scenes::GltfBuilder b;
  scenes::MeshData floor;
  scenes::addQuad(floor, {-1, 0, -1}, {1, 0, -1}, {1, 0, 1}, {-1, 0, 1}, 2, 2, {0, 1, 0});
  b.node("floor", b.mesh("floor", {{floor, b.material("floor", glm::vec3(0.5f))}}));
  tinygltf::Model model = b.finish();
  model.extensionsUsed.push_back("KHR_materials_sheen");
  const fs::path dir = test::scratchDir("ignored"), file = dir / "sheen.gltf";
  scenes::writeModel(model, file.string());
  const std::string warning = "ivgi: warning: " + file.string() + ": extension KHR_materials_sheen";
  auto warnings = [&](const test::Run& r) {
    EXPECT_EQ(r.status, 0) << r.err;
    const auto lines = r.errLines();
    return std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.rfind(warning, 0) == 0; });
  };
  const std::string out = (dir / "f_%04d").string(), size = "16x12";
  EXPECT_EQ(warnings(test::runIvgi({"render", file.string(), "--frames", "0", "--size", size, "--out", out})), 1);
  EXPECT_EQ(warnings(test::runIvgi({"bench", file.string(), "--frames", "1", "--warmup", "0", "--size", size})), 1);
  EXPECT_EQ(warnings(test::runIvgi({"sweep", file.string(), "--method", "none", "--repeats", "1", "--warmup", "0",
                                    "--reference", (dir / "f_0000.exr").string(), "--out", (dir / "sweep").string()})),
            1);
}

TEST(Render, ExrCarriesEveryLayerAndPngIsDisplayReady) {
  auto dir = test::scratchDir("out");
  ASSERT_EQ(test::runIvgi({"render", "--frames", "0", "--size", "64x48", "--out", (dir / "f").string()}).status, 0);
  auto exr = OIIO_NAMESPACE::ImageInput::open((dir / "f_0000.exr").string());
  ASSERT_TRUE(exr);
  const auto& spec = exr->spec();
  EXPECT_EQ(spec.format, OIIO_NAMESPACE::TypeDesc::FLOAT);
  for (const char* c : {"R", "G", "B", "A", "albedo.R", "albedo.G", "albedo.B", "N.X", "N.Y", "N.Z", "Z", "emission.R",
                        "emission.G", "emission.B", "roughness", "metallic"})
    EXPECT_GE(spec.channelindex(c), 0) << c;
  auto png = OIIO_NAMESPACE::ImageInput::open((dir / "f_0000.png").string());
  ASSERT_TRUE(png);
  EXPECT_EQ(png->spec().nchannels, 3);
  EXPECT_EQ(png->spec().format, OIIO_NAMESPACE::TypeDesc::UINT8);
}

TEST(Render, ResumeSkipsFramesThatExist) {
  auto dir = test::scratchDir("out");
  std::string pattern = (dir / "f_%04d").string();
  ASSERT_EQ(test::runIvgi({"render", "--frames", "0-1", "--size", "32x24", "--out", pattern}).status, 0);
  auto stamp = fs::last_write_time(dir / "f_0000.exr");
  fs::remove(dir / "f_0001.png");  // frame 1 is incomplete: it must be rendered again
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  auto r = test::runIvgi({"render", "--frames", "0-2", "--size", "32x24", "--out", pattern, "--resume"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(fs::last_write_time(dir / "f_0000.exr"), stamp) << "frame 0 was complete and is kept";
  EXPECT_TRUE(fs::exists(dir / "f_0001.png"));
  EXPECT_TRUE(fs::exists(dir / "f_0002.exr"));
  std::ifstream in(dir / "f.json");
  // Frames 1 and 2 rendered now; frame 0's record kept from the run that rendered it.
  const auto frames = nlohmann::json::parse(in)["frames"];
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0]["frame"], 0);
  EXPECT_EQ(frames[1]["frame"], 1);
  EXPECT_EQ(frames[2]["frame"], 2);
}

// Images written while the next frames render (a GPU's default) are those written in turn (a CPU
// device's), and the sidecar lists every frame in order with its files.
TEST(Render, FramesWrittenAheadAreThoseWrittenInTurn) {
  std::map<std::string, nlohmann::json> frames;
  for (const char* ahead : {"0", "3"}) {
    auto dir = test::scratchDir(std::string("ahead") + ahead);
    auto r = test::runIvgi(
        {"render", "--frames", "0-6", "--size", "48x36", "--write-ahead", ahead, "--out", (dir / "f_%04d").string()});
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / "f.json");
    frames[ahead] = nlohmann::json::parse(in)["frames"];
    ASSERT_EQ(frames[ahead].size(), 7u);
    for (int f = 0; f < 7; ++f) {
      EXPECT_EQ(frames[ahead][f]["frame"], f);
      EXPECT_GT(frames[ahead][f]["wallMs"].get<double>(), 0.0);
      for (const auto& file : frames[ahead][f]["files"]) EXPECT_TRUE(fs::exists(file.get<std::string>())) << file;
    }
  }
  for (int f = 0; f < 7; ++f)
    for (size_t k = 0; k < 2; ++k)
      EXPECT_EQ(test::readFile(frames["0"][f]["files"][k].get<std::string>()),
                test::readFile(frames["3"][f]["files"][k].get<std::string>()))
          << frames["3"][f]["files"][k];
  EXPECT_NE(test::runIvgi({"render", "--write-ahead", "17", "--frames", "0", "--size", "8x8"}).status, 0);
}

// A frame whose images cannot be written ends the run with its error; the frames before it, and
// those after it already written, keep their records.
TEST(FrameWriter, AFailedFrameLeavesTheOthersRecorded) {
  auto dir = test::scratchDir("writer");
  const std::string sidecarPath = (dir / "f.json").string();
  {
    cli::Sidecar sidecar(sidecarPath, nlohmann::json::object(), false);
    cli::FrameWriter writer(sidecar, 3,
                            [](const std::vector<std::string>& paths, const image::FrameChannels&) {
                              if (paths[0] == "f2.exr") throw std::runtime_error("f2.exr: disk full");
                            },
                            {});
    EXPECT_THROW(
        {
          for (int frame = 0; frame < 5; ++frame) {
            gi::FrameResult result;
            result.channels.width = result.channels.height = 1;
            result.channels.radiance.assign(1, glm::vec4(1.0f));
            writer.add(frame, frame / 24.0, {"f" + std::to_string(frame) + ".exr"}, std::move(result),
                       std::chrono::steady_clock::now());
          }
          writer.finish();
        },
        std::runtime_error);
  }
  std::ifstream in(sidecarPath);
  const nlohmann::json written = nlohmann::json::parse(in);
  std::vector<int> recorded;
  for (const auto& f : written["frames"]) recorded.push_back(f["frame"].get<int>());
  EXPECT_EQ(recorded, (std::vector<int>{0, 1, 3, 4}));
}

TEST(Render, AnInterruptedRunLeavesNoPartialFile) {
  auto dir = test::scratchDir("out");
  pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    setenv("IVGI_VALIDATION", "0", 1);
    int devnull = open("/dev/null", O_WRONLY);
    dup2(devnull, 2);
    // Frames written while the next render, as on a GPU: the writers' temporaries go too.
    execl(IVGI_BINARY, IVGI_BINARY, "render", "--size", "1600x1200", "--supersample", "2", "--write-ahead", "3",
          "--out", (dir / "f_%04d").c_str(), nullptr);
    _exit(127);
  }
  // Interrupt once the first frame is on disk, i.e. in the middle of the run.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (!fs::exists(dir / "f_0000.png") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  kill(pid, SIGINT);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGINT);
  size_t frames = 0;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".ivgi-tmp"), std::string::npos) << "temporary left behind: " << name;
    if (e.path().extension() == ".exr" || e.path().extension() == ".png") {
      ++frames;
      auto in = OIIO_NAMESPACE::ImageInput::open(e.path().string());
      ASSERT_TRUE(in) << name << " is not a complete image";
      std::vector<float> pixels(size_t(in->spec().image_pixels()) * in->spec().nchannels);
      EXPECT_TRUE(in->read_image(0, 0, 0, -1, OIIO_NAMESPACE::TypeDesc::FLOAT, pixels.data()))
          << name << " is truncated";
    }
  }
  EXPECT_GE(frames, 1u);
  EXPECT_LT(frames, 2u * 49u) << "the run was interrupted before the end";
}

TEST(Scene, BuiltInScenesRoundTripThroughGltf) {
  auto dir = test::scratchDir("scene");
  for (const char* name : {"cornell", "furnace"}) {
    std::string file = (dir / (std::string(name) + ".gltf")).string();
    auto w = test::runIvgi({"scene", name, "--cells", "3", "--out", file});
    ASSERT_EQ(w.status, 0) << w.err;
    auto fromFile = test::runIvgi({"info", file});
    auto builtin = test::runIvgi({"info", name, "--cells", "3"});
    ASSERT_EQ(fromFile.status, 0) << fromFile.err;
    auto line = [](const std::string& text, const std::string& key) {
      return text.substr(text.find(key), text.find('\n', text.find(key)) - text.find(key));
    };
    EXPECT_EQ(line(fromFile.out, "triangles"), line(builtin.out, "triangles"));
    EXPECT_EQ(line(fromFile.out, "surfels"), line(builtin.out, "surfels"));
    EXPECT_EQ(line(fromFile.out, "animations"), line(builtin.out, "animations"));
  }
  auto glb = test::runIvgi({"scene", "cornell", "--out", (dir / "c.glb").string()});
  EXPECT_EQ(glb.status, 0) << glb.err;
  EXPECT_EQ(test::runIvgi({"info", (dir / "c.glb").string()}).status, 0);
}

TEST(Info, PrintsTheFigures) {
  auto r = test::runIvgi({"info", "cornell", "--cells", "2"});
  ASSERT_EQ(r.status, 0) << r.err;
  for (const char* key : {"meshes", "triangles", "surfels", "animations", "block moves", "2.000 s", "cameras",
                          "Cornell camera", "39.31 deg", "lights", "bounds", "warnings"})
    EXPECT_NE(r.out.find(key), std::string::npos) << key << " missing from:\n" << r.out;
  // The Cornell box's room is open at the front and its blocks at the bottom; the furnace is a closed cube.
  EXPECT_NE(r.out.find("closed       0 of 6 drawn instances"), std::string::npos) << r.out;
  auto furnace = test::runIvgi({"info", "furnace", "--cells", "2"});
  ASSERT_EQ(furnace.status, 0) << furnace.err;
  EXPECT_NE(furnace.out.find("closed       1 of 1 drawn instances"), std::string::npos) << furnace.out;
}

TEST(Devices, ChosenByIndexNameOrEnvironment) {
  auto list = test::runIvgi({"devices"});
  ASSERT_EQ(list.status, 0);
  EXPECT_NE(list.out.find("[0]"), std::string::npos);
  auto dir = test::scratchDir("out");
  std::vector<std::string> args = {"render", "--frames",          "0", "--size", "16x16", "--format", "png",
                                   "--out",  (dir / "f").string()};
  auto byIndex = args;
  byIndex.insert(byIndex.end(), {"--device", "0"});
  EXPECT_EQ(test::runIvgi(byIndex).status, 0);
  EXPECT_EQ(test::runIvgi(args, {{"IVGI_DEVICE", "0"}}).status, 0);
  auto bad = test::runIvgi(args, {{"IVGI_DEVICE", "7"}});
  EXPECT_NE(bad.status, 0);
  EXPECT_NE(bad.err.find("device index 7 out of range"), std::string::npos) << bad.err;
}
