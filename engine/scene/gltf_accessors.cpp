#include "scene/gltf_accessors.h"

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

namespace {
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
  if (a.sparse.isSparse) fail(path_, where_, "sparse accessors are not supported");
  count_ = a.count;
  components_ = componentCount(a.type);
  componentType_ = a.componentType;
  normalized_ = a.normalized;
  const size_t size = componentBytes(a.componentType);
  if (components_ == 0 || size == 0) fail(path_, where_, "unsupported accessor type");
  element_ = size * size_t(components_);
  if (a.bufferView < 0) return;  // all zeros, as the specification says
  if (size_t(a.bufferView) >= model.bufferViews.size())
    fail(path_, where_, "buffer view " + std::to_string(a.bufferView) + " does not exist");
  const tinygltf::BufferView& view = model.bufferViews[size_t(a.bufferView)];
  if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
    fail(path_, where_, "buffer " + std::to_string(view.buffer) + " does not exist");
  const std::vector<unsigned char>& buffer = model.buffers[size_t(view.buffer)].data;
  stride_ = view.byteStride ? view.byteStride : element_;
  if (stride_ < element_) fail(path_, where_, "byte stride smaller than an element");
  if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
    fail(path_, where_, "buffer view runs past the end of its buffer");
  const size_t need = count_ == 0 ? 0 : a.byteOffset + stride_ * (count_ - 1) + element_;
  if (a.byteOffset > view.byteLength ||
      (count_ > 0 && (stride_ * (count_ - 1)) / stride_ != count_ - 1) || need > view.byteLength ||
      need < a.byteOffset)
    fail(path_, where_, std::to_string(count_) + " elements run past the end of their buffer view");
  data_ = buffer.data() + view.byteOffset + a.byteOffset;
}

double AccessorReader::get(size_t i, int c) const {
  if (!data_) return 0.0;
  const unsigned char* p = data_ + i * stride_ + size_t(c) * (element_ / size_t(components_));
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

}  // namespace penumbra::gltf
