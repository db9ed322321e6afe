#include "tests/engine/scene/draco_encode.h"

#include <draco/compression/decode.h>
#include <draco/compression/encode.h>
#include <draco/mesh/triangle_soup_mesh_builder.h>

#include <memory>

namespace penumbra::test {

DracoEncoded encodeDraco(const std::vector<std::array<float, 3>>& positions,
                         const std::vector<std::array<float, 2>>& uvs,
                         const std::vector<uint32_t>& indices) {
  const size_t faces = indices.size() / 3;
  draco::TriangleSoupMeshBuilder builder;
  builder.Start(int(faces));
  const int pos = builder.AddAttribute(draco::GeometryAttribute::POSITION, 3, draco::DT_FLOAT32);
  const int tex = builder.AddAttribute(draco::GeometryAttribute::TEX_COORD, 2, draco::DT_FLOAT32);
  for (size_t f = 0; f < faces; ++f) {
    const uint32_t* v = &indices[3 * f];
    const draco::FaceIndex face{uint32_t(f)};
    builder.SetAttributeValuesForFace(pos, face, positions[v[0]].data(), positions[v[1]].data(),
                                      positions[v[2]].data());
    builder.SetAttributeValuesForFace(tex, face, uvs[v[0]].data(), uvs[v[1]].data(),
                                      uvs[v[2]].data());
  }
  const std::unique_ptr<draco::Mesh> mesh = builder.Finalize();
  DracoEncoded out;
  if (!mesh) return out;
  draco::Encoder encoder;
  encoder.SetAttributeQuantization(draco::GeometryAttribute::POSITION, 16);
  encoder.SetAttributeQuantization(draco::GeometryAttribute::TEX_COORD, 14);
  draco::EncoderBuffer buffer;
  if (!encoder.EncodeMeshToBuffer(*mesh, &buffer).ok()) return out;
  out.bytes.assign(buffer.data(), buffer.size());
  out.positionId = mesh->attribute(pos)->unique_id();
  out.uvId = mesh->attribute(tex)->unique_id();
  draco::DecoderBuffer in;
  in.Init(buffer.data(), buffer.size());
  draco::Decoder decoder;
  auto decoded = decoder.DecodeMeshFromBuffer(&in);
  if (decoded.ok()) {
    out.points = decoded.value()->num_points();
    out.faces = decoded.value()->num_faces();
  }
  return out;
}

}  // namespace penumbra::test
