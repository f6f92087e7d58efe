#!/usr/bin/env bash
# Installs every Debian package ivgi needs to build, run and test. Idempotent; safe to re-run.
set -euo pipefail
packages=(
  build-essential cmake pkg-config clang-format clang libclang-rt-14-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  glslang-tools libspirv-cross-c-shared-dev
  libglm-dev libtinygltf-dev libstb-dev
  libopenimageio-dev openimageio-tools
  libcli11-dev nlohmann-json3-dev
  libembree-dev libmeshoptimizer-dev python3 python3-matplotlib
  libgtest-dev libgmock-dev libbenchmark-dev
  assimp-testmodels
  slurm-wlm munge
)
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q
$sudo apt-get install -y -q --no-install-recommends "${packages[@]}"
