#pragma once
// Reads glTF accessors with every check the glTF spec implies: indices in range, views inside
// buffers, sparse substitution, normalized integers, and no NaN/Inf in float data. Each failure is
// a LoadError naming the file and what was read.
#include <tiny_gltf.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "engine/scene/scene.h"

namespace ivgi::scene {

class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& m, const std::string& source) : m_(m), source_(source) {}

  [[noreturn]] void fail(const std::string& what) const;

  // Values of accessor `index` as floats, `components` per element (checked against the type).
  std::vector<float> floats(int index, int components, const std::string& what) const;

  // Integer values (indices, joints), as stored.
  std::vector<uint32_t> uints(int index, int components, const std::string& what) const;

  size_t count(int index, const std::string& what) const;

 private:
  const tinygltf::Accessor& accessor(int index, const std::string& what) const;

  static uint32_t rawUint(int type, const uint8_t* p, int c);

  float component(const tinygltf::Accessor& a, const uint8_t* p, int c) const;

  // Bytes of `count` elements of `elementSize` at `offset` (stride 0 = packed) in buffer view `view`.
  const uint8_t* viewData(int view, size_t offset, size_t count, size_t elementSize, size_t* stride,
                          const std::string& what) const;

  void forEachElement(const tinygltf::Accessor& a, int index, const std::string& what,
                      const std::function<void(size_t, const uint8_t*)>& visit) const;

  const tinygltf::Model& m_;
  std::string source_;
};

}  // namespace ivgi::scene
