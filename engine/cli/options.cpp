#include "engine/cli/options.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>

namespace ivgi::cli {

std::vector<int> FrameRange::frames() const {
  std::vector<int> out;
  for (int f = first; f <= last; f += step) out.push_back(f);
  return out;
}

FrameRange parseFrameRange(const std::string& text) {
  static const std::regex re(R"(^\s*(\d+)(?:\s*-\s*(\d+))?(?::(\d+))?\s*$)");
  std::smatch m;
  if (!std::regex_match(text, m, re))
    throw SettingsError("--frames '" + text + "': expected A, A-B or A-B:STEP with frame numbers >= 0");
  FrameRange r;
  try {
    r.first = std::stoi(m[1]);
    r.last = m[2].matched ? std::stoi(m[2]) : r.first;
    r.step = m[3].matched ? std::stoi(m[3]) : 1;
  } catch (const std::out_of_range&) {
    throw SettingsError("--frames '" + text + "': frame number too large");
  }
  if (r.last < r.first) throw SettingsError("--frames '" + text + "': the last frame comes before the first");
  if (r.step < 1) throw SettingsError("--frames '" + text + "': the step must be at least 1");
  return r;
}

void parseSize(const std::string& text, uint32_t& width, uint32_t& height) {
  static const std::regex re(R"(^\s*(\d{1,9})\s*[xX]\s*(\d{1,9})\s*$)");
  std::smatch m;
  if (!std::regex_match(text, m, re)) throw SettingsError("--size '" + text + "': expected WIDTHxHEIGHT, e.g. 640x360");
  width = uint32_t(std::stoul(m[1]));
  height = uint32_t(std::stoul(m[2]));
  if (width == 0 || height == 0) throw SettingsError("--size '" + text + "': width and height must be at least 1");
}

std::vector<std::string> parseFormats(const std::string& text) {
  std::vector<std::string> out;
  size_t start = 0;
  while (start <= text.size()) {
    size_t comma = text.find(',', start);
    std::string f = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    if (f != "exr" && f != "png") throw SettingsError("--format '" + text + "': formats are exr and png");
    if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

Shard parseShard(const std::string& text) {
  Shard s;
  if (text == "slurm") {
    auto number = [](const char* name, long fallback) {
      const char* v = std::getenv(name);
      if (!v || !*v) {
        if (fallback >= 0) return fallback;
        throw SettingsError(std::string("--shard slurm: ") + name + " is not set (not a Slurm job array task?)");
      }
      char* end = nullptr;
      const long n = std::strtol(v, &end, 10);
      if (*end || n < 0) throw SettingsError(std::string("--shard slurm: ") + name + "='" + v + "' is not a number");
      return n;
    };
    const long id = number("SLURM_ARRAY_TASK_ID", -1), count = number("SLURM_ARRAY_TASK_COUNT", -1);
    const long min = number("SLURM_ARRAY_TASK_MIN", 0), step = std::max(number("SLURM_ARRAY_TASK_STEP", 1), 1L);
    if (id < min || (id - min) % step != 0 || (id - min) / step >= count)
      throw SettingsError("--shard slurm: task " + std::to_string(id) + " is not in its array of " +
                          std::to_string(count));
    s.index = uint32_t((id - min) / step), s.count = uint32_t(count);
    return s;
  }
  static const std::regex re(R"(^\s*(\d{1,6})\s*/\s*(\d{1,6})\s*$)");
  std::smatch m;
  if (!std::regex_match(text, m, re)) throw SettingsError("--shard '" + text + "': expected I/N (0 <= I < N) or slurm");
  s.index = uint32_t(std::stoul(m[1])), s.count = uint32_t(std::stoul(m[2]));
  if (s.count < 1 || s.index >= s.count) throw SettingsError("--shard '" + text + "': expected I/N with 0 <= I < N");
  return s;
}

std::vector<int> shardFrames(const std::vector<int>& frames, const Shard& shard,
                             const std::function<int(int)>& chainStart) {
  std::vector<int> out;
  size_t run = 0;  // the runs of frames of one chain, counted in order
  for (size_t i = 0; i < frames.size(); ++i) {
    if (i > 0 && chainStart(frames[i]) != chainStart(frames[i - 1])) ++run;
    if (run % shard.count == shard.index) out.push_back(frames[i]);
  }
  return out;
}

OutputPattern::OutputPattern(const std::string& pattern) {
  std::string p = pattern;
  std::string ext = std::filesystem::path(p).extension().string();
  if (ext == ".exr" || ext == ".png") p = p.substr(0, p.size() - ext.size());
  static const std::regex conv(R"(%(0?)(\d*)d)");
  std::smatch m;
  if (std::regex_search(p, m, conv)) {
    hasNumber_ = true;
    zeroPad_ = m[1].length() > 0;
    width_ = m[2].length() ? std::stoi(m[2]) : 0;
    prefix_ = m.prefix();
    suffix_ = m.suffix();
    if (width_ > 12) throw SettingsError("--out '" + pattern + "': frame number width above 12");
  } else {
    prefix_ = p + "_";  // no conversion given: append the frame number
    hasNumber_ = true;
    zeroPad_ = true;
    width_ = 4;
  }
  if (prefix_.find('%') != std::string::npos || suffix_.find('%') != std::string::npos)
    throw SettingsError("--out '" + pattern + "': only one %d conversion (e.g. %04d) is allowed");
  if (prefix_.empty() && suffix_.empty()) throw SettingsError("--out '" + pattern + "': empty file name");
}

std::string OutputPattern::path(int frame, const std::string& format) const {
  char number[32];
  if (zeroPad_)
    std::snprintf(number, sizeof number, "%0*d", width_, frame);
  else
    std::snprintf(number, sizeof number, "%*d", width_, frame);
  return prefix_ + number + suffix_ + "." + format;
}

std::string OutputPattern::sidecar() const {
  std::string stem = prefix_ + suffix_;
  while (!stem.empty() && (stem.back() == '_' || stem.back() == '-' || stem.back() == '.')) stem.pop_back();
  if (stem.empty() || stem.back() == '/') stem += "render";
  return stem + ".json";
}

std::string OutputPattern::directory() const {
  auto dir = std::filesystem::path(prefix_ + "0" + suffix_).parent_path();
  return dir.empty() ? "." : dir.string();
}

}  // namespace ivgi::cli
