#include "engine/cli/frame_pairs.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <regex>

#include "engine/core/errors.h"

namespace ivgi::cli {

namespace {

namespace fs = std::filesystem;

enum class Kind { File, Folder, Pattern };

Kind kindOf(const std::string& path) {
  if (path.find('%') != std::string::npos) return Kind::Pattern;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return Kind::Folder;
  if (fs::is_regular_file(path, ec)) return Kind::File;
  // A device or a pipe (/dev/zero) has no end to read to.
  if (fs::exists(path, ec)) throw SettingsError(path + ": not a regular file or a folder");
  throw SettingsError(path + ": no such file or folder");
}

// A folder's .exr files by name.
std::map<std::string, std::string> folderFrames(const std::string& folder) {
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::directory_iterator(folder))
    if (entry.is_regular_file() && entry.path().extension() == ".exr" && entry.path().filename().string()[0] != '.')
      out[entry.path().filename().string()] = entry.path().string();
  return out;
}

// The files a pattern's one %d conversion (%d, %4d, %04d) matches, by frame number.
std::map<std::string, std::string> patternFrames(const std::string& pattern) {
  static const std::regex conversion(R"(%0?\d*d)");
  std::smatch m;
  const std::string name = fs::path(pattern).filename().string();
  if (!std::regex_search(name, m, conversion) || m.suffix().str().find('%') != std::string::npos)
    throw SettingsError(pattern + ": a pattern names its frame number with one %d (e.g. f_%04d.exr)");
  const std::string prefix = m.prefix(), suffix = m.suffix();
  fs::path folder = fs::path(pattern).parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) throw SettingsError(pattern + ": no folder " + folder.string());
  std::map<std::string, std::string> out;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string file = entry.path().filename().string();
    if (file.size() <= prefix.size() + suffix.size() || file.compare(0, prefix.size(), prefix) != 0 ||
        file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0)
      continue;
    const std::string number = file.substr(prefix.size(), file.size() - prefix.size() - suffix.size());
    if (number.find_first_not_of("0123456789") != std::string::npos) continue;
    out["frame " + std::to_string(std::stoull(number))] = entry.path().string();
  }
  return out;
}

}  // namespace

std::vector<FramePair> pairFrames(const std::string& test, const std::string& reference) {
  const Kind kind = kindOf(test);
  if (kindOf(reference) != kind)
    throw SettingsError("compare " + test + " with " + reference +
                        ": both must be files, both folders, or both patterns with a frame number");
  if (kind == Kind::File) return {{fs::path(test).filename().string(), test, reference}};
  auto frames = kind == Kind::Folder ? folderFrames : patternFrames;
  std::map<std::string, std::string> tests = frames(test), references = frames(reference);
  std::map<std::string, FramePair> pairs;
  for (const auto& [name, path] : tests) pairs[name].test = path;
  for (const auto& [name, path] : references) pairs[name].reference = path;
  std::vector<FramePair> out;
  for (auto& [name, pair] : pairs) {
    pair.name = name;
    out.push_back(pair);
  }
  if (kind == Kind::Pattern)  // by number, not as text
    std::sort(out.begin(), out.end(), [](const FramePair& a, const FramePair& b) {
      return std::stoull(a.name.substr(6)) < std::stoull(b.name.substr(6));
    });
  if (out.empty()) throw SettingsError("no .exr frames in " + test + " or " + reference);
  return out;
}

}  // namespace ivgi::cli
