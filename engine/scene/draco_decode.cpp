#include "scene/draco_decode.h"

#include <draco/compression/decode.h>
#include <draco/core/decoder_buffer.h>

#include <cstring>
#include <memory>

namespace penumbra::gltf {

namespace {

// Every point's value of `attribute` as `components` values of type T.
template <typename T>
void readValues(const draco::PointAttribute& attribute, size_t points, DracoAttribute& out) {
  const size_t components = size_t(out.components);
  out.bytes.assign(points * components * sizeof(T), 0);
  T value[4] = {};
  for (size_t i = 0; i < points; ++i) {
    attribute.ConvertValue<T>(attribute.mapped_index(draco::PointIndex(uint32_t(i))),
                              int8_t(components), value);
    std::memcpy(out.bytes.data() + i * components * sizeof(T), value, components * sizeof(T));
  }
}

void readAttribute(const draco::PointAttribute& attribute, size_t points, DracoAttribute& out) {
  switch (out.componentType) {
    case 5120:
      return readValues<int8_t>(attribute, points, out);
    case 5121:
      return readValues<uint8_t>(attribute, points, out);
    case 5122:
      return readValues<int16_t>(attribute, points, out);
    case 5123:
      return readValues<uint16_t>(attribute, points, out);
    case 5125:
      return readValues<uint32_t>(attribute, points, out);
    default:
      return readValues<float>(attribute, points, out);
  }
}

}  // namespace

std::string decodeDraco(const unsigned char* data, size_t size, DracoMesh& mesh,
                        std::vector<DracoAttribute>& attributes) {
  draco::DecoderBuffer in;
  in.Init(reinterpret_cast<const char*>(data), size);
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (!decoded.ok()) return decoded.status().error_msg_string();
  const std::unique_ptr<draco::Mesh> m = std::move(decoded).value();
  if (!m) return "no mesh in the data";
  mesh.points = m->num_points();
  mesh.indices.resize(size_t(m->num_faces()) * 3);
  for (uint32_t f = 0; f < m->num_faces(); ++f)
    for (int k = 0; k < 3; ++k)
      mesh.indices[size_t(f) * 3 + size_t(k)] = m->face(draco::FaceIndex(f))[k].value();
  for (DracoAttribute& a : attributes) {
    const draco::PointAttribute* attribute = m->GetAttributeByUniqueId(a.uniqueId);
    if (!attribute) return "no attribute of id " + std::to_string(a.uniqueId) + " in the data";
    if (a.components < 1 || a.components > 4) return "an attribute needs 1 to 4 components";
    readAttribute(*attribute, mesh.points, a);
  }
  return "";
}

}  // namespace penumbra::gltf
