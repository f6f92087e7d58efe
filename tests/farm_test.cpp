// Sequences rendered in shards, as render farms run them: the split, the shards' sidecars and
// `ivgi report`, runs killed outright and resumed, and a Slurm job array on a one-node cluster that
// the test starts (tools/farm/local-slurm.sh) and stops.
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fcntl.h>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "engine/cli/options.h"
#include "engine/image/atomic_file.h"
#include "tests/test_support.h"

using namespace ivgi;
namespace fs = std::filesystem;

namespace {

// Every file of `expected` is in `got` with the same bytes.
void expectSameFrames(const fs::path& got, const fs::path& expected) {
  size_t compared = 0;
  for (const auto& e : fs::directory_iterator(expected)) {
    const std::string ext = e.path().extension().string();
    if (ext != ".exr" && ext != ".png") continue;
    ASSERT_TRUE(fs::exists(got / e.path().filename())) << e.path().filename();
    EXPECT_EQ(test::readFile(got / e.path().filename()), test::readFile(e.path())) << e.path().filename() << " differs";
    ++compared;
  }
  EXPECT_GT(compared, 0u);
}

std::vector<std::string> hiddenFiles(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename().string()[0] == '.') out.push_back(e.path().filename().string());
  return out;
}

// A process id that is no longer running: a child that has exited and been reaped.
pid_t deadPid() {
  pid_t pid = fork();
  if (pid == 0) _exit(0);
  waitpid(pid, nullptr, 0);
  return pid;
}

std::string host() {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  return name;
}

// Runs a shell command; its exit status.
int shell(const std::string& command) {
  const int raw = std::system(command.c_str());
  return WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
}

// Whether process `pid` runs (a zombie that nobody reaped has ended).
bool running(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const size_t paren = line.rfind(')');
  return paren != std::string::npos && paren + 2 < line.size() && line[paren + 2] != 'Z';
}

bool waitFor(const std::function<bool()>& condition, double seconds) {
  for (auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
       std::chrono::steady_clock::now() < end;) {
    if (condition()) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return condition();
}

}  // namespace

TEST(Shards, EveryRequestedFrameFallsInExactlyOneStridedShard) {
  const std::vector<int> frames = cli::FrameRange{3, 40, 2}.frames();
  std::vector<int> seen;
  for (uint32_t i = 0; i < 4; ++i) {
    const auto part = cli::shardFrames(frames, cli::parseShard(std::to_string(i) + "/4"));
    for (size_t k = 1; k < part.size(); ++k)
      EXPECT_EQ(part[k] - part[k - 1], 8) << "strided: every 4th requested frame";
    seen.insert(seen.end(), part.begin(), part.end());
  }
  std::sort(seen.begin(), seen.end());
  EXPECT_EQ(seen, frames);
  EXPECT_EQ(cli::shardFrames({0, 1, 2}, cli::parseShard("5/8")), std::vector<int>{}) << "more shards than frames";
  // Chains of 4 frames (0-3, 4-7, …) go whole to a shard, every 3rd from the shard's index.
  const auto chainOf = [](int frame) { return frame - frame % 4; };
  EXPECT_EQ(cli::shardFrames(cli::FrameRange{2, 17, 1}.frames(), cli::parseShard("1/3"), chainOf),
            (std::vector<int>{4, 5, 6, 7, 16, 17}));
  EXPECT_EQ(cli::shardFrames(cli::FrameRange{2, 17, 3}.frames(), cli::parseShard("0/2"), chainOf),
            (std::vector<int>{2, 8, 11, 17}))
      << "2 | 5 | 8, 11 | 14 | 17: runs 0, 2 and 4";
  for (const char* bad : {"4/4", "1/0", "-1/3", "a/b", "3", ""})
    EXPECT_THROW(cli::parseShard(bad), SettingsError) << bad;
  // A Slurm array 10-16:2 (10, 12, 14, 16): task 14 is the third of four.
  setenv("SLURM_ARRAY_TASK_ID", "14", 1), setenv("SLURM_ARRAY_TASK_MIN", "10", 1);
  setenv("SLURM_ARRAY_TASK_STEP", "2", 1), setenv("SLURM_ARRAY_TASK_COUNT", "4", 1);
  const cli::Shard s = cli::parseShard("slurm");
  EXPECT_EQ(s.index, 2u);
  EXPECT_EQ(s.count, 4u);
  unsetenv("SLURM_ARRAY_TASK_ID");
  EXPECT_THROW(cli::parseShard("slurm"), SettingsError) << "outside a job array";
  for (const char* v : {"SLURM_ARRAY_TASK_MIN", "SLURM_ARRAY_TASK_STEP", "SLURM_ARRAY_TASK_COUNT"}) unsetenv(v);
}

// Shards written one after another into one folder give, byte for byte, what one run writes: each
// shard's first frame makes the static links again, and no image depends on where a shard starts.
TEST(Shards, AssembleTheSequenceOneRunWritesBitForBit) {
  const fs::path dir = test::scratchDir("farm");
  const std::vector<std::string> common = {"render", "cornell", "--frames", "0-8", "--size", "64x48", "--cells", "6"};
  auto render = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = common;
    args.insert(args.end(), {"--out", (dir / out / "f_%04d").string()});
    args.insert(args.end(), extra.begin(), extra.end());
    return test::runIvgi(args);
  };
  ASSERT_EQ(render("one", {}).status, 0);
  for (int i = 0; i < 3; ++i) ASSERT_EQ(render("shards", {"--shard", std::to_string(i) + "/3"}).status, 0);
  expectSameFrames(dir / "shards", dir / "one");
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(fs::exists(dir / "shards" / ("f.shard-" + std::to_string(i) + "-of-3.json"))) << i;
  EXPECT_FALSE(fs::exists(dir / "shards" / "f.json")) << "no two shards write one sidecar";

  const fs::path summary = dir / "summary.json";
  test::Run report = test::runIvgi({"report", (dir / "shards" / "f_%04d").string(), "--json", summary.string()});
  EXPECT_EQ(report.status, 0) << report.out << report.err;
  EXPECT_NE(report.out.find("9 frames requested, 9 rendered, 0 missing (from 3 sidecars)"), std::string::npos)
      << report.out;
  const auto j = nlohmann::json::parse(std::ifstream(summary));
  EXPECT_EQ(j["frames"].size(), 9u);
  EXPECT_GT(j["medianGpuMs"]["total"].get<double>(), 0.0);

  EXPECT_EQ(report.err.find("warning"), std::string::npos) << "one device, one setting: " << report.err;
  EXPECT_TRUE(j["warnings"].empty());

  // Shards solved with other receivers (as on another kind of device) are named.
  ASSERT_EQ(render("mixed", {"--shard", "0/2", "--receiver-tol", "0.4"}).status, 0);
  ASSERT_EQ(render("mixed", {"--shard", "1/2", "--receiver-tol", "0"}).status, 0);
  report = test::runIvgi({"report", (dir / "mixed" / "f_%04d").string()});
  EXPECT_EQ(report.status, 0) << report.err;
  EXPECT_NE(report.err.find("different receiver tolerances (0, 0.4"), std::string::npos) << report.err;
  EXPECT_NE(report.err.find("--receiver-tol"), std::string::npos) << report.err;
  // Shards that pruned the moving block's links to itself differently are named too.
  ASSERT_EQ(render("rigid", {"--shard", "0/2", "--rigid", "once"}).status, 0);
  ASSERT_EQ(render("rigid", {"--shard", "1/2", "--rigid", "every-frame"}).status, 0);
  report = test::runIvgi({"report", (dir / "rigid" / "f_%04d").string()});
  EXPECT_EQ(report.status, 0) << report.err;
  EXPECT_NE(report.err.find("rigid objects' links to themselves differently (every frame, once"), std::string::npos)
      << report.err;
  EXPECT_EQ(report.err.find("receiver tolerances"), std::string::npos) << "the same tolerance: " << report.err;

  fs::remove(dir / "shards" / "f_0004.exr");
  report = test::runIvgi({"report", (dir / "shards" / "f_%04d").string()});
  EXPECT_EQ(report.status, 1);
  EXPECT_NE(report.out.find("missing: 4\n"), std::string::npos) << report.out;
}

// ar's chains (--restart-every): a frame starts from the solution of the frame before, so a run that
// starts inside a chain solves the frames of the chain before it first, without writing them; shards
// take whole chains. Every way of cutting the sequence writes what one run writes, byte for byte.
TEST(Shards, ArChainsGiveTheSameFramesWhereverARunStarts) {
  const fs::path dir = test::scratchDir("farm-ar");
  auto render = [&](const std::string& out, std::vector<std::string> extra) {
    std::vector<std::string> args = {
        "render", "cornell",         "--method", "ar",       "--cells", "4",     "--size",
        "32x24",  "--restart-every", "3",        "--format", "exr",     "--out", (dir / out / "f_%04d").string()};
    args.insert(args.end(), extra.begin(), extra.end());
    return test::runIvgi(args);
  };
  ASSERT_EQ(render("one", {"--frames", "0-6"}).status, 0);
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(render("shards", {"--frames", "0-6", "--shard", std::to_string(i) + "/2"}).status, 0);
  expectSameFrames(dir / "shards", dir / "one");
  const auto frames = nlohmann::json::parse(std::ifstream(dir / "shards" / "f.shard-1-of-2.json"))["frames"];
  ASSERT_EQ(frames.size(), 3u) << "shard 1 of 2 takes the chain 3-5";
  for (const auto& f : frames) {
    EXPECT_EQ(f["solver"]["warm"].get<double>(), f["frame"].get<int>() == 3 ? 0.0 : 1.0) << f.dump();
  }
  // A run of frame 5 alone solves 3 and 4 first; a resumed run solves what a missing frame needs.
  ASSERT_EQ(render("alone", {"--frames", "5"}).status, 0);
  EXPECT_EQ(test::readFile(dir / "alone" / "f_0005.exr"), test::readFile(dir / "one" / "f_0005.exr"));
  fs::copy(dir / "one", dir / "resumed");
  fs::remove(dir / "resumed" / "f_0004.exr");
  ASSERT_EQ(render("resumed", {"--frames", "0-6", "--resume"}).status, 0);
  expectSameFrames(dir / "resumed", dir / "one");
}

// --resume removes the temporaries of runs that are over (a run lock nobody holds, or a process of
// this host that is gone) and never those of a run still alive (its lock held) or of another host
// whose state it cannot know.
TEST(Shards, ResumeRemovesOnlyTheTemporariesOfRunsThatEnded) {
  const fs::path dir = test::scratchDir("temporaries");
  const std::string me = host(), dead = me + "~" + std::to_string(deadPid()),
                    alive = me + "~" + std::to_string(deadPid());
  auto touch = [&](const std::string& name) { std::ofstream(dir / name) << "x"; };
  touch(".ivgi-run~" + dead + ".lock");  // a run killed outright: its lock file, unlocked
  touch(".ivgi-tmp~" + dead + "~f_0003.exr");
  touch(".ivgi-tmp~" + me + "~" + std::to_string(deadPid()) + "~f_0004.png");  // no lock file, this host, gone
  touch(".ivgi-tmp-" + std::to_string(deadPid()) + "-f_0005.exr");             // named as before run locks
  touch(".ivgi-tmp~elsewhere~123~f_0006.exr");                                 // another host, no lock: unknown
  touch(".ivgi-run~" + alive + ".lock");                                       // a run still alive: its lock held
  touch(".ivgi-tmp~" + alive + "~f_0007.exr");
  const int held = open((dir / (".ivgi-run~" + alive + ".lock")).c_str(), O_RDWR);
  ASSERT_EQ(flock(held, LOCK_EX | LOCK_NB), 0);
  {
    image::RunLock mine(dir.string());
    touch(".ivgi-tmp~" + me + "~" + std::to_string(getpid()) + "~f_0008.exr");  // this process's own
    EXPECT_EQ(image::removeDeadTemporaries(dir.string()), 4u);
    std::vector<std::string> left = hiddenFiles(dir);
    std::sort(left.begin(), left.end());
    std::vector<std::string> expected = {".ivgi-run~" + alive + ".lock",
                                         ".ivgi-run~" + me + "~" + std::to_string(getpid()) + ".lock",
                                         ".ivgi-tmp~" + alive + "~f_0007.exr", ".ivgi-tmp~elsewhere~123~f_0006.exr",
                                         ".ivgi-tmp~" + me + "~" + std::to_string(getpid()) + "~f_0008.exr"};
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(left, expected);
  }
  EXPECT_FALSE(fs::exists(dir / (".ivgi-run~" + me + "~" + std::to_string(getpid()) + ".lock")))
      << "a run removes its lock";
  close(held);  // the run ends: its files go at the next resume
  EXPECT_EQ(image::removeDeadTemporaries(dir.string()), 2u);
}

// A render killed with kill -9 leaves no file under a final name that is not whole; --resume renders
// what is missing, removes what the killed run left, and the frames are those of an unbroken run.
TEST(Shards, AKilledRunIsResumedToTheSameFrames) {
  const fs::path dir = test::scratchDir("killed");
  const std::string args = "render cornell --method pt --spp 512 --size 48x36 --frames 0-5 --threads 1 --out ";
  ASSERT_EQ(shell("'" IVGI_BINARY "' " + args + "'" + (dir / "whole/f_%04d").string() + "' 2>/dev/null"), 0);
  const fs::path out = dir / "killed";
  ASSERT_EQ(shell("'" IVGI_BINARY "' " + args + "'" + (out / "f_%04d").string() + "' 2>/dev/null & echo $! > '" +
                  (dir / "pid").string() + "'"),
            0);
  ASSERT_TRUE(waitFor([&] { return fs::exists(out / "f_0001.png"); }, 60)) << "the run did not get going";
  const pid_t pid = pid_t(std::stol(test::readFile(dir / "pid")));
  kill(pid, SIGKILL);
  ASSERT_TRUE(waitFor([&] { return !running(pid); }, 10));
  EXPECT_FALSE(fs::exists(out / "f_0005.png")) << "killed before the end";
  EXPECT_FALSE(hiddenFiles(out).empty()) << "the killed run's lock (and maybe a temporary) stays behind";
  // The resume in a process of its own, as a farm would run it: the killed run and its lock are another's.
  test::Run resumed =
      test::runIvgiProcess({"render", "cornell", "--method", "pt", "--spp", "512", "--size", "48x36", "--frames", "0-5",
                            "--threads", "1", "--out", (out / "f_%04d").string(), "--resume"});
  ASSERT_EQ(resumed.status, 0) << resumed.err;
  EXPECT_TRUE(hiddenFiles(out).empty()) << "left behind: " << (hiddenFiles(out).empty() ? "" : hiddenFiles(out)[0]);
  expectSameFrames(out, dir / "whole");
}

// The recipe end to end on a one-node Slurm cluster: a four-task job array of the animated Cornell
// box, one task killed (SIGKILL) after its first frame, the array submitted again with the same
// command; every frame the same bytes as one process writes, the report complete, and no daemon
// left running.
TEST(Shards, ASlurmJobArrayKilledAndResubmitted) {
  if (geteuid() != 0) GTEST_SKIP() << "starting munged, slurmctld and slurmd needs root";
  if (shell("command -v slurmctld >/dev/null && command -v munged >/dev/null && command -v sbatch >/dev/null") != 0)
    GTEST_SKIP() << "slurm-wlm and munge are not installed (ci/install-deps.sh installs them)";
  const fs::path dir = test::scratchDir("slurm"), cluster = dir / "cluster", work = dir / "work";
  const std::string tools = std::string(IVGI_SOURCE_DIR) + "/tools/farm/";
  fs::create_directories(work);
  ASSERT_EQ(shell("'" + tools + "local-slurm.sh' start '" + cluster.string() + "'"), 0) << "see " << cluster / "log";
  struct Stop {  // the daemons stop however the test ends
    std::string command;
    ~Stop() { shell(command); }
  } stop{"'" + tools + "local-slurm.sh' stop '" + cluster.string() + "'"};
  const std::string slurm = "SLURM_CONF='" + (cluster / "slurm.conf").string() + "' ";
  const std::string submit = "cd '" + work.string() + "' && " + slurm +
                             "IVGI='" IVGI_BINARY "' sbatch --parsable --export=ALL " +
                             "--array=0-3 --cpus-per-task=1 '" + tools + "render-array.sbatch' cornell frames/f_%04d " +
                             "--method pt --spp 512 --size 48x36 --frames 0-11 > '" + (dir / "job").string() + "'";
  auto idle = [&] { return shell(slurm + "squeue -h | grep -q .") != 0; };

  ASSERT_EQ(shell(submit), 0);
  const std::string job = test::readFile(dir / "job").substr(0, test::readFile(dir / "job").find_first_of("\n;"));
  // Shard 2 renders frames 2, 6, 10: killed once frame 2 is written.
  ASSERT_TRUE(waitFor([&] { return fs::exists(work / "frames" / "f_0002.png"); }, 120));
  EXPECT_EQ(shell(slurm + "scancel --signal=KILL --full " + job + "_2"), 0);
  ASSERT_TRUE(waitFor(idle, 120));
  EXPECT_FALSE(fs::exists(work / "frames" / "f_0010.exr")) << "the killed task did not finish";
  std::map<std::string, fs::file_time_type> before;
  for (const auto& e : fs::directory_iterator(work / "frames"))
    if (e.path().extension() == ".exr") before[e.path().filename().string()] = fs::last_write_time(e.path());

  ASSERT_EQ(shell(submit), 0);  // the same array again: --resume renders only what is missing
  ASSERT_TRUE(waitFor(idle, 120));
  for (const auto& [name, time] : before)
    EXPECT_EQ(fs::last_write_time(work / "frames" / name), time) << name << " rendered twice";
  EXPECT_TRUE(hiddenFiles(work / "frames").empty()) << "left behind: " << hiddenFiles(work / "frames")[0];

  ASSERT_EQ(test::runIvgi({"render", "cornell", "--method", "pt", "--spp", "512", "--size", "48x36", "--frames", "0-11",
                           "--out", (dir / "one" / "f_%04d").string()})
                .status,
            0);
  expectSameFrames(work / "frames", dir / "one");
  test::Run report = test::runIvgi({"report", (work / "frames" / "f_%04d").string()});
  EXPECT_EQ(report.status, 0) << report.out;
  EXPECT_NE(report.out.find("12 frames requested, 12 rendered, 0 missing (from 4 sidecars)"), std::string::npos)
      << report.out;

  shell(stop.command);
  // "[/]…": a pattern that does not match the shell running pgrep.
  EXPECT_NE(shell("pgrep -f '[/]" + cluster.string().substr(1) + "' > /dev/null"), 0) << "a daemon is still running";
}
