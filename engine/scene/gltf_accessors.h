// Reading a glTF file's accessors for gltf_io.cpp: every byte an accessor reads checked to lie
// inside its buffer view and buffer, normalised integers scaled, errors naming the file and
// the element. Internal to the glTF reader.
#pragma once

#include "scene/scene.h"

#include <tiny_gltf.h>

#include <cstddef>
#include <string>
#include <vector>

namespace penumbra::gltf {

// Throws SceneError("path: where: message").
[[noreturn]] void fail(const std::string& path, const std::string& where,
                       const std::string& message);

// A factor as a user wrote it: 0.7, not 0.700000.
std::string number(double v);

// "array[i]".
std::string indexed(const char* array, size_t i);

// Bytes of one component of a glTF component type (5120-5126); 0 for any other.
size_t componentBytes(int type);

// An accessor's elements as doubles (normalised integers scaled to [0, 1] or [-1, 1]), after
// checking every byte it reads lies inside its buffer view and buffer. A sparse accessor's
// elements are its base's (zeros without a buffer view) with the listed ones replaced; its
// indices must be strictly increasing and below the count, as the specification says.
class AccessorReader {
 public:
  AccessorReader(const std::string& path, const tinygltf::Model& model, int index,
                 const std::string& where);

  size_t count() const { return count_; }
  int components() const { return components_; }
  bool isFloat() const { return componentType_ == TINYGLTF_COMPONENT_TYPE_FLOAT; }

  // Component c of element i.
  double get(size_t i, int c) const;

  const std::string& where() const { return where_; }

 private:
  double scaled(double v, double max) const { return normalized_ ? v / max : v; }
  // The component at p, of the accessor's component type.
  double decode(const unsigned char* p) const;
  // Checks that `count` elements of `element` bytes, `stride` apart, from byteOffset of buffer
  // view `viewIndex` lie inside it and its buffer; their first byte. `what` names them.
  const unsigned char* viewData(const tinygltf::Model& model, int viewIndex, size_t byteOffset,
                                size_t count, size_t element, size_t* stride,
                                const std::string& what) const;
  void readSparse(const tinygltf::Model& model, const tinygltf::Accessor& a);

  const std::string& path_;
  std::string where_;
  const unsigned char* data_ = nullptr;
  size_t count_ = 0, stride_ = 0, element_ = 0;
  // A sparse accessor's replaced elements: their indices, ascending, and their values (tightly
  // packed elements, the i-th for sparseIndices_[i]).
  std::vector<size_t> sparseIndices_;
  const unsigned char* sparseValues_ = nullptr;
  int components_ = 0, componentType_ = 0;
  bool normalized_ = false;
};

// A primitive's vertex indices (its `indices` accessor's, each checked to be below
// `vertexCount`, or 0, 1, 2, ... without one). Throws SceneError naming `where`.indices.
std::vector<uint32_t> readIndices(const std::string& path, const tinygltf::Model& model,
                                  const tinygltf::Primitive& primitive, size_t vertexCount,
                                  const std::string& where);

}  // namespace penumbra::gltf
