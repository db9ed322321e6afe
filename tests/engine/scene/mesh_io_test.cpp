// Tests for the PLY and OBJ/MTL readers, on small files written by the tests
// themselves: the three PLY encodings, skipping of unknown data, error messages
// for damaged files, and the MTL-to-Material mapping.
#include "scene/mesh_io.h"
#include "scene/scene_loader.h"

#include "tests/engine/scene/expect_scene_error.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

namespace penumbra {
namespace {

using test::expectSceneError;

// Builds binary PLY bodies value by value in a chosen byte order.
class Bytes {
 public:
  explicit Bytes(bool bigEndian) : bigEndian_(bigEndian) {}
  // Appends each value with its own type's size, e.g. add(uint8_t(3), 1.0f).
  template <typename... T>
  Bytes& add(T... values) {
    (putOne(values), ...);
    return *this;
  }
  const std::string& str() const { return data_; }

 private:
  template <typename T>
  void putOne(T value) {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, &value, sizeof(T));
    // The test machine is little-endian (x86-64 / arm64 Linux).
    for (size_t i = 0; i < sizeof(T); ++i) data_ += char(raw[bigEndian_ ? sizeof(T) - 1 - i : i]);
  }

  bool bigEndian_;
  std::string data_;
};

// The quad every PLY test encodes: in the xz plane, counter-clockwise seen from +y.
const vec3 kQuad[4] = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(1, 0, -1), vec3(0, 0, -1)};

void expectQuadMesh(const Mesh& mesh, bool withNormalsAndUvs) {
  ASSERT_EQ(mesh.vertexCount, 4u);
  ASSERT_EQ(mesh.positions.size(), 4u);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(mesh.positions[v], kQuad[v]) << "vertex " << v;
  ASSERT_EQ(mesh.indices, (std::vector<uint32_t>{0, 1, 2, 0, 2, 3}));
  EXPECT_EQ(mesh.materialIds, (std::vector<uint32_t>{0, 0}));
  for (size_t t = 0; t < 2; ++t) {
    const vec3 p0 = mesh.positions[mesh.indices[3 * t]];
    const vec3 n = glm::cross(mesh.positions[mesh.indices[3 * t + 1]] - p0,
                              mesh.positions[mesh.indices[3 * t + 2]] - p0);
    EXPECT_GT(n.y, 0.0f);
  }
  if (!withNormalsAndUvs) return;
  ASSERT_EQ(mesh.normals.size(), 4u);
  ASSERT_EQ(mesh.uvs.size(), 4u);
  for (int v = 0; v < 4; ++v) {
    EXPECT_NEAR(glm::dot(mesh.normals[v], vec3(0, 1, 0)), 1.0f, 1e-6f);
    EXPECT_EQ(mesh.uvs[v], vec2(kQuad[v].x, -kQuad[v].z));
  }
}

TEST(PlyReader, AsciiWithIgnoredPropertiesAndElements) {
  const std::string path = test::writeOutput("ply/ascii_quad.ply",
                                             "ply\r\n"
                                             "format ascii 1.0\n"
                                             "comment made by hand\n"
                                             "obj_info nothing\n"
                                             "element camera 1\n"
                                             "property float view_px\n"
                                             "property list uchar float stuff\n"
                                             "element vertex 4\n"
                                             "property float x\n"
                                             "property float y\n"
                                             "property float z\n"
                                             "property uchar red\n"
                                             "property float nx\n"
                                             "property float ny\n"
                                             "property float nz\n"
                                             "property float s\n"
                                             "property float t\n"
                                             "element face 1\n"
                                             "property uchar flags\n"
                                             "property list uchar int vertex_indices\n"
                                             "property list int double weights\n"
                                             "element edge 2\n"
                                             "property int vertex1\n"
                                             "property int vertex2\n"
                                             "end_header\n"
                                             "1.5 3 7 8 9\n"
                                             "0 0 0 255 0 2 0 0 0\n"
                                             "1 0 0 12 0 1 0 1 0\n"
                                             "1 0 -1 3 0 1 0 1 1\n"
                                             "0 0 -1 4 0 1 0 0 1\n"
                                             "7 4 0 1 2 3 2 0.5 -1e3\n"
                                             "0 1\n"
                                             "1 2");  // no final newline
  const Mesh mesh = loadPly(path);
  expectQuadMesh(mesh, true);
  EXPECT_EQ(mesh.name, "ascii_quad");
}

// Header for the binary tests: every scalar type as an ignored property, and a
// list of an unusual type, around the ones that matter.
std::string binaryHeader(const char* format, const char* coordinateType, const char* countType,
                         const char* indexType) {
  return std::string("ply\nformat ") + format +
         " 1.0\n"
         "element vertex 4\n"
         "property char a\nproperty ushort b\n" +
         "property " + coordinateType + " x\nproperty " + coordinateType + " y\nproperty " +
         coordinateType + " z\n" +
         "property int16 c\nproperty uint32 d\nproperty float64 e\n"
         "property float texture_u\nproperty float texture_v\n"
         "element face 1\n"
         "property list " +
         countType + " " + indexType +
         " vertex_index\n"
         "property list uint8 int8 junk\n"
         "element extra 1\n"
         "property list ushort float stuff\n"
         "property uint8 last\n"
         "end_header\n";
}

template <typename Coordinate, typename Count, typename Index>
std::string binaryBody(bool bigEndian) {
  Bytes bytes(bigEndian);
  for (const vec3& p : kQuad) {
    bytes.add(int8_t(-3), uint16_t(65000));
    bytes.add(Coordinate(p.x), Coordinate(p.y), Coordinate(p.z));
    bytes.add(int16_t(-2), uint32_t(4000000000u), 2.5);
    bytes.add(float(p.x), float(-p.z));
  }
  bytes.add(Count(4), Index(0), Index(1), Index(2), Index(3));
  bytes.add(uint8_t(2), int8_t(-1), int8_t(5));
  bytes.add(uint16_t(1), 9.0f, uint8_t(1));
  return bytes.str();
}

TEST(PlyReader, BinaryLittleEndian) {
  const std::string path = test::writeOutput(
      "ply/le_quad.ply", binaryHeader("binary_little_endian", "float", "uchar", "int") +
                             binaryBody<float, uint8_t, int32_t>(false));
  const Mesh mesh = loadPly(path);
  expectQuadMesh(mesh, false);
  EXPECT_TRUE(mesh.normals.empty());
  ASSERT_EQ(mesh.uvs.size(), 4u);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(mesh.uvs[v], vec2(kQuad[v].x, -kQuad[v].z));
}

TEST(PlyReader, BinaryBigEndian) {
  const std::string path = test::writeOutput(
      "ply/be_quad.ply", binaryHeader("binary_big_endian", "double", "int", "uint") +
                             binaryBody<double, int32_t, uint32_t>(true));
  const Mesh mesh = loadPly(path);
  expectQuadMesh(mesh, false);
  ASSERT_EQ(mesh.uvs.size(), 4u);
  for (int v = 0; v < 4; ++v) EXPECT_EQ(mesh.uvs[v], vec2(kQuad[v].x, -kQuad[v].z));
}

TEST(PlyReader, ZeroNormalsAreRebuiltFromFaces) {
  const std::string path =
      test::writeOutput("ply/zero_normal.ply",
                        "ply\nformat ascii 1.0\nelement vertex 3\n"
                        "property float x\nproperty float y\nproperty float z\n"
                        "property float nx\nproperty float ny\nproperty float nz\n"
                        "element face 1\nproperty list uchar uint vertex_indices\n"
                        "end_header\n"
                        "0 0 0 0 0 0\n1 0 0 0 0 2\n0 1 0 0 0 1\n3 0 1 2\n");
  const Mesh mesh = loadPly(path);
  ASSERT_EQ(mesh.normals.size(), 3u);
  for (const vec3& n : mesh.normals) EXPECT_NEAR(n.z, 1.0f, 1e-6f);
}

TEST(PlyReader, HalfAUvPairIsIgnored) {
  const std::string path =
      test::writeOutput("ply/only_s.ply",
                        "ply\nformat ascii 1.0\nelement vertex 3\n"
                        "property float x\nproperty float y\nproperty float z\n"
                        "property float s\n"
                        "element face 1\nproperty list uchar uint vertex_indices\n"
                        "end_header\n"
                        "0 0 0 5\n1 0 0 5\n0 1 0 5\n3 0 1 2\n");
  const Mesh mesh = loadPly(path);
  EXPECT_TRUE(mesh.uvs.empty());
  EXPECT_TRUE(mesh.normals.empty());
  EXPECT_EQ(mesh.triangleCount(), 1u);
}

const char* kAsciiVertexHeader =
    "ply\nformat ascii 1.0\nelement vertex 4\n"
    "property float x\nproperty float y\nproperty float z\n";

TEST(PlyReader, UnknownTypeNamesFileAndLine) {
  const std::string path =
      test::writeOutput("ply/bad_type.ply", std::string(kAsciiVertexHeader) +
                                                "property flaot w\n"
                                                "element face 0\nend_header\n");
  expectSceneError([&] { loadPly(path); },
                   {"bad_type.ply", "line 7", "unknown property type 'flaot'"});
}

TEST(PlyReader, IndexOutOfRange) {
  const std::string path = test::writeOutput(
      "ply/bad_index.ply", std::string(kAsciiVertexHeader) +
                               "element face 2\nproperty list uchar int vertex_indices\n"
                               "end_header\n0 0 0\n1 0 0\n1 0 1\n0 0 1\n"
                               "3 0 1 2\n3 0 2 900\n");
  expectSceneError([&] { loadPly(path); },
                   {"bad_index.ply", "face 1: vertex index 900 out of range (4 vertices)"});
  const std::string negative = test::writeOutput(
      "ply/negative_index.ply", std::string(kAsciiVertexHeader) +
                                    "element face 1\nproperty list uchar int vertex_indices\n"
                                    "end_header\n0 0 0\n1 0 0\n1 0 1\n0 0 1\n3 0 -1 2\n");
  expectSceneError([&] { loadPly(negative); }, {"negative_index.ply", "vertex index -1"});
}

TEST(PlyReader, TruncatedBinary) {
  std::string body = binaryBody<float, uint8_t, int32_t>(false);
  body.resize(body.size() - 12);  // cuts into the face list
  const std::string path = test::writeOutput(
      "ply/truncated.ply", binaryHeader("binary_little_endian", "float", "uchar", "int") + body);
  expectSceneError([&] { loadPly(path); },
                   {"truncated.ply", "truncated binary data in element 'face'"});
}

TEST(PlyReader, HugeListLengthIsTruncationNotAllocation) {
  Bytes bytes(false);
  for (int i = 0; i < 12; ++i) bytes.add(float(i));
  bytes.add(uint32_t(0xFFFFFFFFu), int32_t(0));
  const std::string path =
      test::writeOutput("ply/huge_list.ply",
                        "ply\nformat binary_little_endian 1.0\nelement vertex 4\n"
                        "property float x\nproperty float y\nproperty float z\n"
                        "element face 1\nproperty list uint int vertex_indices\nend_header\n" +
                            bytes.str());
  expectSceneError([&] { loadPly(path); }, {"huge_list.ply", "truncated binary data"});
}

TEST(PlyReader, HugeHeaderCountIsRejectedUpFront) {
  const std::string path = test::writeOutput(
      "ply/huge_count.ply",
      "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n"
      "property float x\nproperty float y\nproperty float z\n"
      "element face 18446744073709551615\nproperty list uchar int vertex_indices\n"
      "end_header\n" +
          std::string(48, '\0'));
  expectSceneError([&] { loadPly(path); }, {"huge_count.ply", "element 'vertex'"});
  const std::string ascii = test::writeOutput(
      "ply/huge_count_ascii.ply", std::string(kAsciiVertexHeader) +
                                      "element face 99999999999\n"
                                      "property list uchar int vertex_indices\nend_header\n"
                                      "0 0 0\n1 0 0\n1 0 1\n0 0 1\n3 0 1 2\n");
  expectSceneError([&] { loadPly(ascii); }, {"huge_count_ascii.ply", "element 'face'"});
}

TEST(PlyReader, OtherMalformedFiles) {
  const std::string notPly = test::writeOutput("ply/not_ply.ply", "solid cube\nendsolid\n");
  expectSceneError([&] { loadPly(notPly); }, {"not_ply.ply", "not a PLY file"});

  const std::string badNumber = test::writeOutput(
      "ply/bad_number.ply", std::string(kAsciiVertexHeader) +
                                "element face 0\nproperty list uchar int vertex_indices\n"
                                "end_header\n0 0 0\n1 zero 0\n1 0 1\n0 0 1\n");
  expectSceneError([&] { loadPly(badNumber); }, {"bad_number.ply", "line 11", "'zero'"});

  const std::string shortAscii = test::writeOutput(
      "ply/short_ascii.ply", std::string(kAsciiVertexHeader) +
                                 "element face 1\nproperty list uchar int vertex_indices\n"
                                 "end_header\n0 0 0\n1 0 0\n1 0 1\n0 0 1\n3 0 1\n");
  expectSceneError([&] { loadPly(shortAscii); }, {"short_ascii.ply", "element 'face'"});

  const std::string noHeaderEnd = test::writeOutput("ply/no_end.ply", kAsciiVertexHeader);
  expectSceneError([&] { loadPly(noHeaderEnd); }, {"no_end.ply", "end_header"});

  const std::string noZ =
      test::writeOutput("ply/no_z.ply",
                        "ply\nformat ascii 1.0\nelement vertex 1\n"
                        "property float x\nproperty float y\n"
                        "element face 0\nproperty list uchar int vertex_indices\n"
                        "end_header\n0 0\n");
  expectSceneError([&] { loadPly(noZ); }, {"no_z.ply", "'z'"});

  expectSceneError([] { loadPly(test::outputPath("ply/does_not_exist.ply")); },
                   {"does_not_exist.ply", "cannot open file"});
}

// ---------------------------------------------------------------------------- OBJ

const char* kMtl =
    "newmtl light\nKd 0.5 0.5 0.5\nKe 10 8 6\n"
    "newmtl glass\nKd 1 1 1\nd 0.5\nNi 1.5\nillum 4\n"
    "newmtl glossy\nKd 0.1 0.1 0.1\nKs 0.9 0.6 0.3\nNs 100\n"
    "newmtl textured\nKd 0.7 0.6 0.5\nmap_Kd textures\\wood.png\n"
    "newmtl chrome\nKs 0.95 0.95 0.95\nNs 1000\n"
    "newmtl matte\nKd 0.2 0.4 0.6\n";

const char* kObj =
    "mtllib scene.mtl\n"
    "v 0 0 0\nv 1 0 0\nv 1 0 -1\nv 0 0 -1\nv 0 1 0\n"
    "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
    "vn 0 1 0\nvn 0 0 1\n"
    "f 1 2 5\n"  // before any usemtl: gets the default material
    "usemtl light\nf 1/1/1 2/2/1 3/3/1\n"
    "usemtl glass\nf 1/1/2 3/3/2 4/4/2\n"   // same positions, other normal: new vertices
    "usemtl glossy\nf 1/1/1 3/3/1 4/4/1\n"  // reuses the light face's corners 1 and 3
    "usemtl textured\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
    "usemtl chrome\nf 5 2 1\n"
    "usemtl matte\nf -5 -4 -1\n";

// One folder per test: CTest runs the tests that load it in parallel processes.
std::string testObjFolder() {
  return std::string("obj_") + ::testing::UnitTest::GetInstance()->current_test_info()->name();
}

ObjData loadTestObj() {
  test::writeOutput(testObjFolder() + "/scene.mtl", kMtl);
  return loadObj(test::writeOutput(testObjFolder() + "/scene.obj", kObj));
}

uint32_t materialIndex(const ObjData& data, const std::string& name) {
  for (size_t i = 0; i < data.materials.size(); ++i) {
    if (data.materials[i].name == name) return uint32_t(i);
  }
  ADD_FAILURE() << "no material " << name;
  return 0;
}

TEST(ObjReader, MapsMtlMaterials) {
  const ObjData data = loadTestObj();
  ASSERT_EQ(data.materials.size(), 7u);  // six from the MTL and the default
  ASSERT_EQ(data.diffuseMaps.size(), data.materials.size());

  const Material& light = data.materials[materialIndex(data, "light")];
  EXPECT_TRUE(light.isEmissive());
  EXPECT_EQ(light.type, Material::Type::Diffuse);
  EXPECT_EQ(light.emission, vec3(10, 8, 6));
  EXPECT_EQ(light.albedo, vec3(0.5f));

  const Material& glass = data.materials[materialIndex(data, "glass")];
  EXPECT_EQ(glass.type, Material::Type::Dielectric);
  EXPECT_FLOAT_EQ(glass.ior, 1.5f);
  EXPECT_FALSE(glass.isEmissive());

  const Material& glossy = data.materials[materialIndex(data, "glossy")];
  EXPECT_EQ(glossy.type, Material::Type::Conductor);
  EXPECT_EQ(glossy.albedo, vec3(0.9f, 0.6f, 0.3f));
  // alpha = sqrt(2 / (Ns + 2)) and alpha = roughness².
  const float alpha = std::sqrt(2.0f / 102.0f);
  EXPECT_NEAR(glossy.roughness * glossy.roughness, alpha, 1e-5f);

  const Material& chrome = data.materials[materialIndex(data, "chrome")];
  EXPECT_EQ(chrome.type, Material::Type::Mirror);
  EXPECT_EQ(chrome.albedo, vec3(0.95f));

  const Material& matte = data.materials[materialIndex(data, "matte")];
  EXPECT_EQ(matte.type, Material::Type::Diffuse);
  EXPECT_EQ(matte.albedo, vec3(0.2f, 0.4f, 0.6f));

  const uint32_t textured = materialIndex(data, "textured");
  EXPECT_EQ(data.materials[textured].type, Material::Type::Diffuse);
  EXPECT_EQ(data.materials[textured].albedo, vec3(0.7f, 0.6f, 0.5f));
  const std::string folder =
      std::filesystem::path(test::outputPath(testObjFolder() + "/scene.obj")).parent_path();
  EXPECT_EQ(data.diffuseMaps[textured], folder + "/textures/wood.png");
  for (size_t i = 0; i < data.materials.size(); ++i) {
    if (i != textured) {
      EXPECT_EQ(data.diffuseMaps[i], "") << data.materials[i].name;
    }
  }

  const Material& fallback = data.materials.back();
  EXPECT_EQ(fallback.name, "default");
  EXPECT_EQ(fallback.type, Material::Type::Diffuse);
  EXPECT_EQ(fallback.albedo, vec3(0.8f));
}

TEST(ObjReader, BuildsDeindexedMeshKeepingWinding) {
  const ObjData data = loadTestObj();
  const Mesh& mesh = data.mesh;
  EXPECT_EQ(mesh.name, "scene");
  ASSERT_EQ(mesh.triangleCount(), 8u);  // the quad became two triangles
  ASSERT_EQ(mesh.materialIds.size(), 8u);
  ASSERT_EQ(mesh.positions.size(), mesh.vertexCount);
  ASSERT_EQ(mesh.normals.size(), mesh.vertexCount);
  ASSERT_EQ(mesh.uvs.size(), mesh.vertexCount);
  for (uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertexCount);

  // Unique (v, vt, vn) triples: 1,2,5 bare; 1/1/1 2/2/1 3/3/1 4/4/1; 1/1/2 3/3/2 4/4/2;
  // 5 2 1 are already there as bare corners, and -5 -4 -1 = 1 2 5.
  EXPECT_EQ(mesh.vertexCount, 3u + 4u + 3u);

  const std::vector<std::string> expectedMaterials = {"default",  "light",    "glass",  "glossy",
                                                      "textured", "textured", "chrome", "matte"};
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    EXPECT_EQ(data.materials[mesh.materialIds[t]].name, expectedMaterials[t]) << "triangle " << t;
  }

  // The emissive face is counter-clockwise seen from +y in the file; so it must stay.
  const vec3 p0 = mesh.positions[mesh.indices[3]];
  const vec3 lightNormal =
      glm::cross(mesh.positions[mesh.indices[4]] - p0, mesh.positions[mesh.indices[5]] - p0);
  EXPECT_GT(lightNormal.y, 0.0f);
  EXPECT_EQ(mesh.uvs[mesh.indices[5]], vec2(1, 1));
  EXPECT_EQ(mesh.normals[mesh.indices[3]], vec3(0, 1, 0));
  EXPECT_EQ(mesh.normals[mesh.indices[6]], vec3(0, 0, 1));  // the glass face's own normal

  // Corners without a vn get a normal from their faces rather than zero.
  for (const vec3& n : mesh.normals) EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f);
}

TEST(ObjReader, MissingMtlFallsBackToDefaultMaterial) {
  const std::string path = test::writeOutput("obj/no_mtl.obj",
                                             "mtllib nowhere.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                             "usemtl ghost\nf 1 2 3\n");
  const ObjData data = loadObj(path);
  ASSERT_EQ(data.materials.size(), 1u);
  EXPECT_EQ(data.materials[0].name, "default");
  EXPECT_EQ(data.mesh.materialIds, (std::vector<uint32_t>{0}));
  EXPECT_TRUE(data.mesh.normals.empty());
  EXPECT_TRUE(data.mesh.uvs.empty());
  // Never silently: a warning names the library.
  ASSERT_EQ(data.warnings.size(), 1u);
  EXPECT_NE(data.warnings[0].find("mtllib 'nowhere.mtl' not found"), std::string::npos)
      << data.warnings[0];
  const Scene scene = sceneFromObj(path);
  ASSERT_EQ(scene.warnings.size(), 1u);
  EXPECT_NE(scene.warnings[0].find("no_mtl.obj: mtllib 'nowhere.mtl'"), std::string::npos)
      << scene.warnings[0];
}

TEST(ObjReader, Errors) {
  expectSceneError([] { loadObj(test::outputPath("obj/x.obj")); }, {"x.obj", "cannot open file"});

  const std::string badIndex =
      test::writeOutput("obj/bad_index.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
  expectSceneError([&] { loadObj(badIndex); }, {"bad_index.obj", "out of bounds"});

  const std::string beforeStart = test::writeOutput(
      "obj/before_start.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -9\nf -9 -1 -2 -3\n");
  expectSceneError([&] { loadObj(beforeStart); }, {"before_start.obj"});

  const std::string zeroIndex =
      test::writeOutput("obj/zero_index.obj", "v 0 0 0\nv 1 0 0\nf 0 1 2\n");
  expectSceneError([&] { loadObj(zeroIndex); }, {"zero_index.obj"});
}

TEST(MtlMapping, RulesInOrder) {
  ObjMaterialDesc desc;
  desc.diffuse = vec3(0.3f);
  EXPECT_EQ(materialFromMtl(desc).type, Material::Type::Diffuse);

  desc.illum = 7;
  desc.ior = 1.33f;
  Material water = materialFromMtl(desc);
  EXPECT_EQ(water.type, Material::Type::Dielectric);
  EXPECT_FLOAT_EQ(water.ior, 1.33f);

  desc = {};
  desc.specular = vec3(0.8f);
  desc.illum = 3;
  EXPECT_EQ(materialFromMtl(desc).type, Material::Type::Mirror);

  desc.illum = 2;
  desc.shininess = 0.0f;  // the broadest lobe there is
  Material rough = materialFromMtl(desc);
  EXPECT_EQ(rough.type, Material::Type::Conductor);
  EXPECT_FLOAT_EQ(rough.roughness, 1.0f);

  desc.shininess = 999.0f;
  EXPECT_GE(materialFromMtl(desc).roughness, 0.02f);

  desc.emission = vec3(0.0f, 0.0f, 1.0f);  // emission wins over everything
  EXPECT_EQ(materialFromMtl(desc).type, Material::Type::Diffuse);
  EXPECT_TRUE(materialFromMtl(desc).isEmissive());
}

}  // namespace
}  // namespace penumbra
