#pragma once
// The error every layer throws for a setting the user gave that cannot be used: out of range,
// malformed, or beyond what the device can hold. Its message names the option (e.g. "--bins 70:
// must be 1 to 64"); the command prints it as one line and exits non-zero.
#include <stdexcept>

namespace ivgi {

struct SettingsError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

}  // namespace ivgi
