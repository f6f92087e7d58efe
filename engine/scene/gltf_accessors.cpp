#include "engine/scene/gltf_accessors.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace ivgi::scene {

void AccessorReader::fail(const std::string& what) const { throw LoadError(source_ + ": " + what); }

std::vector<float> AccessorReader::floats(int index, int components, const std::string& what) const {
  const auto& a = accessor(index, what);
  if (tinygltf::GetNumComponentsInType(a.type) != components)
    fail(what + ": accessor " + std::to_string(index) + " has " +
         std::to_string(tinygltf::GetNumComponentsInType(a.type)) + " components, expected " +
         std::to_string(components));
  std::vector<float> out;  // sized once the data it declares proved to be in its buffers
  forEachElement(a, index, what, [&](size_t element, const uint8_t* p) {
    if (out.empty()) out.resize(size_t(a.count) * components, 0.0f);
    for (int c = 0; c < components; ++c) out[element * components + c] = component(a, p, c);
  });
  out.resize(size_t(a.count) * components, 0.0f);  // an accessor of zeros alone
  for (float v : out)
    if (!std::isfinite(v)) fail(what + ": accessor " + std::to_string(index) + " holds a NaN or infinite value");
  return out;
}

std::vector<uint32_t> AccessorReader::uints(int index, int components, const std::string& what) const {
  const auto& a = accessor(index, what);
  if (tinygltf::GetNumComponentsInType(a.type) != components)
    fail(what + ": accessor " + std::to_string(index) + " has the wrong type");
  if (a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      a.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(what + ": accessor " + std::to_string(index) + " must hold unsigned integers");
  std::vector<uint32_t> out;  // sized once the data it declares proved to be in its buffers
  forEachElement(a, index, what, [&](size_t element, const uint8_t* p) {
    if (out.empty()) out.resize(size_t(a.count) * components, 0u);
    for (int c = 0; c < components; ++c) out[element * components + c] = rawUint(a.componentType, p, c);
  });
  out.resize(size_t(a.count) * components, 0u);  // an accessor of zeros alone
  return out;
}

size_t AccessorReader::count(int index, const std::string& what) const { return accessor(index, what).count; }

const tinygltf::Accessor& AccessorReader::accessor(int index, const std::string& what) const {
  if (index < 0 || size_t(index) >= m_.accessors.size())
    fail(what + ": accessor index " + std::to_string(index) + " out of range");
  return m_.accessors[index];
}

uint32_t AccessorReader::rawUint(int type, const uint8_t* p, int c) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return p[c];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p + 2 * c, 2);
      return v;
    }
    default: {
      uint32_t v;
      std::memcpy(&v, p + 4 * c, 4);
      return v;
    }
  }
}

float AccessorReader::component(const tinygltf::Accessor& a, const uint8_t* p, int c) const {
  switch (a.componentType) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p + 4 * c, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      float v = float(int8_t(p[c]));
      return a.normalized ? std::max(v / 127.0f, -1.0f) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return a.normalized ? p[c] / 255.0f : float(p[c]);
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p + 2 * c, 2);
      return a.normalized ? std::max(v / 32767.0f, -1.0f) : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p + 2 * c, 2);
      return a.normalized ? v / 65535.0f : float(v);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p + 4 * c, 4);
      return float(v);
    }
    default: fail("accessor has an unknown component type " + std::to_string(a.componentType));
  }
}

const uint8_t* AccessorReader::viewData(int view, size_t offset, size_t count, size_t elementSize, size_t* stride,
                                        const std::string& what) const {
  if (view < 0 || size_t(view) >= m_.bufferViews.size())
    fail(what + ": buffer view " + std::to_string(view) + " out of range");
  const auto& bv = m_.bufferViews[view];
  if (bv.buffer < 0 || size_t(bv.buffer) >= m_.buffers.size())
    fail(what + ": buffer " + std::to_string(bv.buffer) + " out of range");
  const auto& buffer = m_.buffers[bv.buffer];
  if (bv.byteOffset + bv.byteLength > buffer.data.size())
    fail(what + ": buffer view " + std::to_string(view) + " reaches past the end of buffer " +
         std::to_string(bv.buffer) + " (" + std::to_string(bv.byteOffset + bv.byteLength) + " > " +
         std::to_string(buffer.data.size()) + " bytes)");
  *stride = bv.byteStride ? bv.byteStride : elementSize;
  // In this order, so that no product of a count and a stride can wrap around.
  if (count > 0 && (offset > bv.byteLength || elementSize > bv.byteLength - offset ||
                    (count - 1) > (bv.byteLength - offset - elementSize) / *stride))
    fail(what + ": accessor data reaches past the end of buffer view " + std::to_string(view));
  return buffer.data.data() + bv.byteOffset + offset;
}

void AccessorReader::forEachElement(const tinygltf::Accessor& a, int index, const std::string& what,
                                    const std::function<void(size_t, const uint8_t*)>& visit) const {
  int componentSize = tinygltf::GetComponentSizeInBytes(a.componentType);
  int components = tinygltf::GetNumComponentsInType(a.type);
  if (componentSize <= 0 || components <= 0)
    fail(what + ": accessor " + std::to_string(index) + " has an invalid type");
  size_t elementSize = size_t(componentSize) * components;
  // Every view the accessor reads is checked to hold what it declares before the first visit, so
  // that a count past its data is refused before anything is sized by it.
  size_t stride = 0, idxStride = 0, valStride = 0;
  const uint8_t* base =
      a.bufferView >= 0 ? viewData(a.bufferView, a.byteOffset, a.count, elementSize, &stride, what) : nullptr;
  const uint8_t *idx = nullptr, *val = nullptr;
  const auto& s = a.sparse;
  if (s.isSparse) {
    int idxSize = tinygltf::GetComponentSizeInBytes(s.indices.componentType);
    if (idxSize <= 0) fail(what + ": sparse accessor " + std::to_string(index) + " has an invalid index type");
    idx = viewData(s.indices.bufferView, s.indices.byteOffset, s.count, idxSize, &idxStride, what);
    val = viewData(s.values.bufferView, s.values.byteOffset, s.count, elementSize, &valStride, what);
  }
  if (base)
    for (size_t i = 0; i < a.count; ++i) visit(i, base + i * stride);
  // no buffer view: zeros, possibly replaced by sparse values below
  if (s.isSparse) {
    for (int i = 0; i < s.count; ++i) {
      uint32_t target = rawUint(s.indices.componentType, idx + i * idxStride, 0);
      if (target >= a.count) fail(what + ": sparse index " + std::to_string(target) + " out of range");
      visit(target, val + i * valStride);
    }
  }
}

}  // namespace ivgi::scene
