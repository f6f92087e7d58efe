#include "engine/cli/sidecar.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>

#include "engine/cli/json_file.h"
#include "engine/cli/machine.h"
#include "engine/cli/statistics.h"

namespace ivgi::cli {

namespace fs = std::filesystem;

Sidecar::Sidecar(std::string path, nlohmann::json header, bool cpuTimes)
    : path_(std::move(path)),
      passKey_(cpuTimes ? "cpuMs" : "gpuMs"),
      totalKey_(cpuTimes ? "totalCpuMs" : "totalGpuMs"),
      medianKey_(cpuTimes ? "medianCpuMs" : "medianGpuMs"),
      json_(std::move(header)) {
  json_["frames"] = nlohmann::json::array();
}

void Sidecar::keepEarlierRecords(const std::vector<int>& frames) {
  std::ifstream in(path_);
  if (!in) return;
  const nlohmann::json earlier = nlohmann::json::parse(in, nullptr, false);
  if (earlier.is_discarded() || !earlier.contains("frames")) return;
  for (const auto& record : earlier["frames"])
    if (record.contains("frame") && std::find(frames.begin(), frames.end(), record["frame"].get<int>()) != frames.end())
      json_["frames"].push_back(record);
}

void Sidecar::addFrame(int frame, double time, const std::vector<std::pair<std::string, double>>& passMs, double wallMs,
                       const std::vector<std::string>& files,
                       const std::vector<std::pair<std::string, double>>& solver) {
  nlohmann::json passes = nlohmann::json::object();
  double total = 0;
  for (const auto& [pass, ms] : passMs) passes[pass] = ms, total += ms;
  nlohmann::json record = {{"frame", frame},
                           {"time", time},
                           {passKey_, passes},
                           {totalKey_, total},
                           {"wallMs", wallMs},
                           {"files", files},
                           {"hostPeakMiB", hostPeakMiB()}};
  for (const auto& [figure, value] : solver) record["solver"][figure] = value;
  json_["frames"].push_back(std::move(record));
}

double Sidecar::medianTotalMs() const {
  std::vector<double> totals;
  for (const auto& record : json_["frames"]) totals.push_back(record[totalKey_].get<double>());
  return percentile(totals, 0.5);
}

void Sidecar::write() {
  std::map<std::string, std::vector<double>> perPass;
  for (const auto& record : json_["frames"]) {
    for (const auto& [pass, ms] : record[passKey_].items()) perPass[pass].push_back(ms.get<double>());
    perPass["total"].push_back(record[totalKey_].get<double>());
  }
  nlohmann::json medians = nlohmann::json::object();
  for (const auto& [pass, ms] : perPass) medians[pass] = percentile(ms, 0.5);
  json_[medianKey_] = medians;
  writeJson(path_, json_);
}

std::string Sidecar::forShard(const std::string& path, const Shard& shard) {
  if (shard.count <= 1) return path;
  const fs::path p(path);
  return (p.parent_path() / (p.stem().string() + ".shard-" + std::to_string(shard.index) + "-of-" +
                             std::to_string(shard.count) + p.extension().string()))
      .string();
}

std::vector<std::string> sidecarsOf(const OutputPattern& pattern) {
  const fs::path own(pattern.sidecar());
  const fs::path folder = own.parent_path().empty() ? fs::path(".") : own.parent_path();
  const std::regex shard(std::regex_replace(own.stem().string(), std::regex(R"([.^$|()\[\]{}*+?\\])"), R"(\$&)") +
                         R"(\.shard-\d+-of-\d+\.json)");
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    const std::string name = entry.path().filename().string();
    if (name == own.filename().string() || std::regex_match(name, shard)) out.push_back(entry.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace ivgi::cli
