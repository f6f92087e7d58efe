// ivgi: global illumination for animated glTF scenes with implicit visibility, on Vulkan compute.
#include "engine/cli/app.h"

int main(int argc, char** argv) { return ivgi::cli::run({argv, argv + argc}); }
