// libFuzzer target: the command line. The input, split at newlines into at most 24 arguments, runs
// `ivgi info` or `ivgi compare`, the commands that need no device and write no file: the first
// argument must name one of them, and the options that write files or open a device (--out, --json,
// --heatmap, --ratio, --device, --method) are dropped with their values. An exit status with a
// one-line refusal is an answer; a crash, a leak, a hang or a sanitizer's report is a finding.
// Built and run by tools/fuzz.sh.
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "engine/cli/app.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> words(1);
  for (size_t i = 0; i < size && words.size() <= 24; ++i)
    if (data[i] == '\n')
      words.emplace_back();
    else if (data[i] != 0)
      words.back() += char(data[i]);
  if (words[0] != "info" && words[0] != "compare") return 0;
  static const std::set<std::string> dropped = {"--out", "--json", "--heatmap", "--ratio", "--device", "--method"};
  std::vector<std::string> args = {"ivgi"};
  for (size_t i = 0; i < words.size(); ++i) {
    const std::string name = words[i].substr(0, words[i].find('='));
    if (dropped.count(name)) {
      if (name == words[i]) ++i;  // and its value
      continue;
    }
    args.push_back(words[i]);
  }
  // A built-in scene at many cells truly draws millions of triangles (`--cells 512`: 3.1 M, 12 s and
  // 1.5 GB in a release build; docs/notes/extremes.md), past the fuzzer's 30 s an input under the
  // sanitizers: a size, not a finding, so 100 cells or more are left out.
  for (size_t i = 1; i < args.size(); ++i) {
    const bool joined = args[i].rfind("--cells=", 0) == 0;
    if (!joined && (args[i] != "--cells" || i + 1 == args.size())) continue;
    const std::string value = joined ? args[i].substr(8) : args[i + 1];
    const bool digits = !value.empty() && value.find_first_not_of("0123456789") == std::string::npos;
    if (digits && (value.size() > 9 || std::stoll(value) >= 100)) return 0;
  }
  std::fflush(stdout);
  ivgi::cli::run(args, nullptr);
  return 0;
}
