#pragma once
// The render's sidecar JSON: its settings, device and counts, and one record per frame (time, the
// milliseconds of each pass, wall-clock milliseconds, files), with the medians over the records.
// It is rewritten after every frame, so that a run killed half-way keeps the records of the frames
// it finished; a sharded render writes one per shard (FILE.shard-I-of-N.json), which `ivgi report`
// gathers.
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engine/cli/options.h"

namespace ivgi::cli {

class Sidecar {
 public:
  // `cpuTimes`: the pass times are pt's CPU milliseconds (keys cpuMs, totalCpuMs, medianCpuMs),
  // else GPU milliseconds (gpuMs, …).
  Sidecar(std::string path, nlohmann::json header, bool cpuTimes);
  const std::string& path() const { return path_; }

  // With --resume: the records the sidecar already at `path` holds of `frames` (those this run
  // skips because their files exist).
  void keepEarlierRecords(const std::vector<int>& frames);
  // `solver`: the solver's figures of the frame (e.g. its bounces).
  void addFrame(int frame, double time, const std::vector<std::pair<std::string, double>>& passMs, double wallMs,
                const std::vector<std::string>& files, const std::vector<std::pair<std::string, double>>& solver);
  void set(const std::string& key, nlohmann::json value) { json_[key] = std::move(value); }
  double medianTotalMs() const;
  void write();

  // The sidecar of `shard`: FILE.json, or FILE.shard-I-of-N.json for one of several shards.
  static std::string forShard(const std::string& path, const Shard& shard);

 private:
  std::string path_, passKey_, totalKey_, medianKey_;
  nlohmann::json json_;
};

// The sidecars of a render with output `pattern`: its own and those of its shards, by name.
std::vector<std::string> sidecarsOf(const OutputPattern& pattern);

}  // namespace ivgi::cli
