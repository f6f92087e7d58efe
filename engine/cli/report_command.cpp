// ivgi report: the summary of a sequence rendered in shards (or in one run), from the sidecars
// the runs wrote: the frames requested, those rendered with their times, those missing.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "engine/cli/commands.h"
#include "engine/cli/json_file.h"
#include "engine/cli/options.h"
#include "engine/cli/sidecar.h"
#include "engine/cli/statistics.h"

namespace ivgi::cli {

namespace {

namespace fs = std::filesystem;

// "3, 5-9, 12": runs of consecutive frames.
std::string runsOf(const std::vector<int>& frames) {
  std::string out;
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    out += (out.empty() ? "" : ", ") + std::to_string(frames[i]) + (j > i ? "-" + std::to_string(frames[j]) : "");
    i = j + 1;
  }
  return out;
}

// "a, b, c".
std::string listed(const std::set<std::string>& items) {
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

}  // namespace

int runReport(const ReportOptions& o) {
  const OutputPattern pattern(o.pattern);
  const std::vector<std::string> sidecars = sidecarsOf(pattern);
  if (sidecars.empty()) throw SettingsError(o.pattern + ": no sidecar " + pattern.sidecar() + " nor shards of it");
  std::vector<int> requested;
  std::vector<std::string> formats;
  std::map<int, nlohmann::json> records;  // by frame; a later sidecar's record of a frame replaces an earlier one
  std::string timeKey = "totalGpuMs", passKey = "gpuMs";
  // What the runs solved on and with: shards that differ here give frames that differ where they meet.
  std::set<std::string> devices, receiverTolerances, rigidObjects;
  for (const std::string& path : sidecars) {
    std::ifstream in(path);
    const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
    if (j.is_discarded() || !j.contains("settings") || !j.contains("frames"))
      throw SettingsError(path + ": not an ivgi sidecar");
    const auto& range = j["settings"]["frames"];
    for (int f : FrameRange{range[0].get<int>(), range[1].get<int>(), range[2].get<int>()}.frames())
      requested.push_back(f);
    for (const auto& f : j["settings"]["formats"]) formats.push_back(f.get<std::string>());
    if (j["settings"]["method"] == "pt") timeKey = "totalCpuMs", passKey = "cpuMs";
    for (const auto& record : j["frames"]) records[record["frame"].get<int>()] = record;
    if (j.contains("device") && j["device"].contains("name")) devices.insert(j["device"]["name"].get<std::string>());
    if (j.contains("solver") && j["solver"].is_object() && j["solver"].contains("receiverTolerance")) {
      char tolerance[64];
      const double unseen = j["solver"].value("unseenTolerance", 1.0);
      std::snprintf(tolerance, sizeof tolerance, unseen != 1.0 ? "%g with --unseen-tol %g" : "%g",
                    j["solver"]["receiverTolerance"].get<double>(), unseen);
      receiverTolerances.insert(tolerance);
    }
    if (j.contains("solver") && j["solver"].is_object() && j["solver"].contains("rigidOnce"))
      rigidObjects.insert(j["solver"]["rigidOnce"].get<bool>() ? "once" : "every frame");
  }
  std::sort(requested.begin(), requested.end());
  requested.erase(std::unique(requested.begin(), requested.end()), requested.end());
  std::sort(formats.begin(), formats.end());
  formats.erase(std::unique(formats.begin(), formats.end()), formats.end());

  std::vector<int> missing, unrecorded;
  std::map<std::string, std::vector<double>> perPass;
  std::vector<double> wall;
  nlohmann::json frames = nlohmann::json::array();
  for (int f : requested) {
    const bool files = std::all_of(formats.begin(), formats.end(),
                                   [&](const std::string& format) { return fs::exists(pattern.path(f, format)); });
    const auto record = records.find(f);
    if (!files) {
      missing.push_back(f);
    } else if (record == records.end()) {
      unrecorded.push_back(f);
    } else {
      for (const auto& [pass, ms] : record->second[passKey].items()) perPass[pass].push_back(ms.get<double>());
      perPass["total"].push_back(record->second[timeKey].get<double>());
      if (record->second.contains("wallMs")) wall.push_back(record->second["wallMs"].get<double>());
      frames.push_back(record->second);
    }
  }
  const size_t done = requested.size() - missing.size();
  std::printf("%s: %zu frames requested, %zu rendered, %zu missing (from %zu sidecars)\n", o.pattern.c_str(),
              requested.size(), done, missing.size(), sidecars.size());
  if (!missing.empty()) std::printf("missing: %s\n", runsOf(missing).c_str());
  if (!unrecorded.empty())
    std::printf("rendered by runs that ended before recording them (no times): %s\n", runsOf(unrecorded).c_str());
  nlohmann::json medians = nlohmann::json::object();
  for (const auto& [pass, ms] : perPass) medians[pass] = percentile(ms, 0.5);
  if (!perPass.empty())
    std::printf("median %s %.2f ms a frame over %zu frames", passKey == "cpuMs" ? "CPU" : "GPU",
                medians["total"].get<double>(), perPass["total"].size());
  if (!wall.empty()) {
    double sum = 0;
    for (double w : wall) sum += w;
    std::printf("; wall clock %.0f ms a frame, %.1f s in all", percentile(wall, 0.5), sum / 1000.0);
  }
  if (!perPass.empty()) std::printf("\n");
  std::vector<std::string> warnings;
  if (devices.size() > 1)
    warnings.push_back("the runs used " + std::to_string(devices.size()) + " devices (" + listed(devices) +
                       "): their frames differ as the devices' arithmetic does");
  if (receiverTolerances.size() > 1)
    warnings.push_back("the runs solved iv with different receiver tolerances (" + listed(receiverTolerances) +
                       "; its default follows the device): give every run the same --receiver-tol and --unseen-tol");
  if (rigidObjects.size() > 1)
    warnings.push_back("the runs pruned iv's rigid objects' links to themselves differently (" + listed(rigidObjects) +
                       "): give every run the same --rigid");
  std::fflush(stdout);
  for (const std::string& w : warnings) std::fprintf(stderr, "ivgi: warning: %s: %s\n", o.pattern.c_str(), w.c_str());
  if (!o.json.empty())
    writeJson(o.json, {{"pattern", o.pattern},
                       {"sidecars", sidecars},
                       {"requested", requested.size()},
                       {"rendered", done},
                       {"missing", missing},
                       {"unrecorded", unrecorded},
                       {passKey == "cpuMs" ? "medianCpuMs" : "medianGpuMs", medians},
                       {"medianWallMs", wall.empty() ? nlohmann::json(nullptr) : nlohmann::json(percentile(wall, 0.5))},
                       {"warnings", warnings},
                       {"frames", frames}});
  return missing.empty() ? 0 : 1;
}

}  // namespace ivgi::cli
