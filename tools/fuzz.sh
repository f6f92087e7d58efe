#!/usr/bin/env bash
# Builds ivgi's libFuzzer targets (tests/fuzz) with clang, AddressSanitizer and
# UndefinedBehaviorSanitizer in build-fuzz/, and runs each for SECONDS (default 600) from its
# corpus in build-fuzz/corpus/TARGET, seeded from ../shared/data, Debian's assimp-testmodels
# (/usr/share/assimp/models) and the golden EXRs (the options fuzzer: command lines of its own). A
# finding stops its target and leaves the input as build-fuzz/crash-*, leak-*, timeout-* or oom-*
# (over 2 GB resident or 30 s an input: the limits a hostile file must stay in).
#   tools/fuzz.sh [SECONDS] [TARGET...]     (needs clang and libclang-rt-14-dev)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-600}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(gltf_scene_fuzzer exr_fuzzer options_fuzzer)
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S . -B build-fuzz -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DBUILD_TESTING=OFF -DIVGI_FUZZERS=ON -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" >/dev/null
cmake --build build-fuzz -j"$(nproc)" --target "${targets[@]}"

seed() {  # seed DIR PATTERN...: copies the files matching the patterns into the corpus DIR once
  local dir=$1
  shift
  mkdir -p "$dir"
  [ -n "$(ls -A "$dir")" ] && return
  for root in ../shared/data /usr/share/assimp/models tests/golden; do
    [ -d "$root" ] || continue
    for pattern in "$@"; do
      find "$root" -name "$pattern" -size -4M -print0 | while IFS= read -r -d '' f; do
        cp "$f" "$dir/$(echo "$f" | md5sum | cut -c1-16)"
      done
    done
  done
}
seed_options() {  # the options fuzzer's seeds: command lines, one argument a line
  local dir=$1 i=0
  mkdir -p "$dir"
  [ -n "$(ls -A "$dir")" ] && return
  local golden=../tests/golden/iv_cornell_f0012.exr
  for line in "info" "info\ncornell\n--tessellate\n4\n--bins\n8" "info\nfurnace\n--cells\n3\n--eps\n1e-6" \
    "info\ncornell\n--direct\npixels\n--light-samples\n64\n--env\n1,1,1\n--env-directions\n16" \
    "compare\n$golden\n$golden" "compare\n$golden\n$golden\n--golden\n--max-flip\n0.1\n--layers\nall" \
    "compare\nf_%04d.exr\ng_%04d.exr\n--max-temporal\n0.01"; do
    printf "$line" >"$dir/seed$((i++))"
  done
}
for target in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$target
  case $target in
    gltf_scene_fuzzer) seed "$corpus" '*.gltf' '*.glb' ;;
    exr_fuzzer) seed "$corpus" '*.exr' ;;
    options_fuzzer) seed_options "$corpus" ;;
  esac
  echo "== $target: $(ls "$corpus" | wc -l) inputs in the corpus, $seconds s"
  (cd build-fuzz && "tests/fuzz/$target" -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=30 -print_final_stats=1 \
    "corpus/$target")
done
