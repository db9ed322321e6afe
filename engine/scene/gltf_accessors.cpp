#include "scene/gltf_accessors.h"

#include <algorithm>
#include <cstring>
#include <sstream>

namespace penumbra::gltf {

void fail(const std::string& path, const std::string& where, const std::string& message) {
  throw SceneError(path + ": " + (where.empty() ? "" : where + ": ") + message);
}

std::string number(double v) {
  std::ostringstream text;
  text << v;
  return text.str();
}

std::string indexed(const char* array, size_t i) {
  return std::string(array) + "[" + std::to_string(i) + "]";
}

size_t componentBytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

namespace {
int componentCount(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR:
      return 1;
    case TINYGLTF_TYPE_VEC2:
      return 2;
    case TINYGLTF_TYPE_VEC3:
      return 3;
    case TINYGLTF_TYPE_VEC4:
      return 4;
    case TINYGLTF_TYPE_MAT4:  // a skin's inverse bind matrices; its columns need no padding
      return 16;
    default:
      return 0;
  }
}
}  // namespace

AccessorReader::AccessorReader(const std::string& path, const tinygltf::Model& model, int index,
                               const std::string& where)
    : path_(path), where_(where + " (accessors[" + std::to_string(index) + "])") {
  if (index < 0 || size_t(index) >= model.accessors.size())
    fail(path, where, "accessor " + std::to_string(index) + " does not exist");
  const tinygltf::Accessor& a = model.accessors[size_t(index)];
  count_ = a.count;
  components_ = componentCount(a.type);
  componentType_ = a.componentType;
  normalized_ = a.normalized;
  const size_t size = componentBytes(a.componentType);
  if (components_ == 0 || size == 0) fail(path_, where_, "unsupported accessor type");
  element_ = size * size_t(components_);
  // Without a buffer view the base is all zeros, as the specification says.
  if (a.bufferView >= 0)
    data_ = viewData(model, a.bufferView, a.byteOffset, count_, element_, &stride_, "elements");
  if (a.sparse.isSparse) readSparse(model, a);
}

const unsigned char* AccessorReader::viewData(const tinygltf::Model& model, int viewIndex,
                                              size_t byteOffset, size_t count, size_t element,
                                              size_t* stride, const std::string& what) const {
  if (viewIndex < 0 || size_t(viewIndex) >= model.bufferViews.size())
    fail(path_, where_, "buffer view " + std::to_string(viewIndex) + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[size_t(viewIndex)];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    fail(path_, where_, "buffer " + std::to_string(view.buffer) + " does not exist");
  const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
  const size_t step = stride && view.byteStride ? view.byteStride : element;
  if (step < element) fail(path_, where_, "byte stride smaller than an element");
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    fail(path_, where_, "buffer view runs past the end of its buffer");
  const size_t need = count == 0 ? 0 : byteOffset + step * (count - 1) + element;
  if (byteOffset > view.byteLength || (count > 0 && (step * (count - 1)) / step != count - 1) ||
      need > view.byteLength || need < byteOffset)
    fail(path_, where_,
         std::to_string(count) + " " + what + " run past the end of their buffer view");
  if (stride) *stride = step;
  return buffer.data() + view.byteOffset + byteOffset;
}

void AccessorReader::readSparse(const tinygltf::Model& model, const tinygltf::Accessor& a) {
  const auto& sparse = a.sparse;
  if (sparse.count < 1 || size_t(sparse.count) > count_)
    fail(path_, where_,
         "sparse count " + std::to_string(sparse.count) + " is not in [1, " +
             std::to_string(count_) + "]");
  const size_t n = size_t(sparse.count);
  const int indexType = sparse.indices.componentType;
  if (indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
      indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      indexType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    fail(path_, where_, "sparse indices must be unsigned byte, short or int");
  if (sparse.indices.byteOffset < 0 || sparse.values.byteOffset < 0)
    fail(path_, where_, "sparse byte offsets must not be negative");
  const size_t indexBytes = componentBytes(indexType);
  const unsigned char* indices =
      viewData(model, sparse.indices.bufferView, size_t(sparse.indices.byteOffset), n, indexBytes,
               nullptr, "sparse indices");
  sparseValues_ = viewData(model, sparse.values.bufferView, size_t(sparse.values.byteOffset), n,
                           element_, nullptr, "sparse values");
  sparseIndices_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const unsigned char* p = indices + i * indexBytes;
    size_t index = p[0];
    if (indexBytes == 2) {
      uint16_t v;
      std::memcpy(&v, p, 2);
      index = v;
    } else if (indexBytes == 4) {
      uint32_t v;
      std::memcpy(&v, p, 4);
      index = v;
    }
    if (index >= count_)
      fail(path_, where_,
           "sparse index " + std::to_string(index) + " is not below the count " +
               std::to_string(count_));
    if (i > 0 && index <= sparseIndices_[i - 1])
      fail(path_, where_, "sparse indices are not strictly increasing");
    sparseIndices_[i] = index;
  }
}

double AccessorReader::get(size_t i, int c) const {
  const size_t component = size_t(c) * (element_ / size_t(components_));
  if (!sparseIndices_.empty()) {
    const auto found = std::lower_bound(sparseIndices_.begin(), sparseIndices_.end(), i);
    if (found != sparseIndices_.end() && *found == i)
      return decode(sparseValues_ + size_t(found - sparseIndices_.begin()) * element_ + component);
  }
  if (!data_) return 0.0;
  return decode(data_ + i * stride_ + component);
}

double AccessorReader::decode(const unsigned char* p) const {
  switch (componentType_) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return scaled(double(p[0]), 255.0);
    case TINYGLTF_COMPONENT_TYPE_BYTE:
      return std::max(scaled(double(int8_t(p[0])), 127.0), -1.0);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return scaled(double(v), 65535.0);
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return std::max(scaled(double(v), 32767.0), -1.0);
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return double(v);
    }
    default: {
      int32_t v;
      std::memcpy(&v, p, 4);
      return double(v);
    }
  }
}

std::vector<uint32_t> readIndices(const std::string& path, const tinygltf::Model& model,
                                  const tinygltf::Primitive& primitive, size_t vertexCount,
                                  const std::string& where) {
  std::vector<uint32_t> order;
  if (primitive.indices < 0) {
    order.resize(vertexCount);
    for (size_t k = 0; k < vertexCount; ++k) order[k] = uint32_t(k);
    return order;
  }
  const AccessorReader indices(path, model, primitive.indices, where + ".indices");
  if (indices.components() != 1 || indices.isFloat())
    fail(path, indices.where(), "indices must be unsigned integer scalars");
  order.resize(indices.count());
  for (size_t k = 0; k < order.size(); ++k) {
    const double i = indices.get(k, 0);
    if (!(i >= 0 && i < double(vertexCount)))
      fail(path, indices.where(),
           "index " + std::to_string(int64_t(i)) + " at " + std::to_string(k) +
               " is not below the " + std::to_string(vertexCount) + " vertices");
    order[k] = uint32_t(i);
  }
  return order;
}

}  // namespace penumbra::gltf
