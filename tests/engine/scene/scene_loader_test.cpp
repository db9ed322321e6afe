// Scene file tests: a valid scene loads as described; every malformed field, missing
// file, bad number and unknown name gives a SceneError naming the file and the field.
#include "scene/scene_loader.h"

#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace penumbra {
namespace {

const char* kValid = R"({
  "render": {"width": 64, "height": 32, "spp": 8, "max_depth": 5},
  "camera": {"eye": [0, 1, 4], "look_at": [0, 0, 0], "fov": 30, "lens_radius": 0.1,
             "focus_distance": 4, "shutter": [0.2, 0.8]},
  "background": [0.1, 0.2, 0.3],
  "textures": {"check": {"type": "checker", "colors": [[1, 1, 1], [0, 0, 0]], "scale": [4, 4]}},
  "materials": {
    "floor": {"type": "diffuse", "albedo": "check"},
    "metal": {"type": "conductor", "color": [0.9, 0.8, 0.7], "roughness": 0.4},
    "glass": {"type": "dielectric", "ior": 1.33},
    "lamp": {"type": "emissive", "radiance": [5, 5, 5]}},
  "objects": [
    {"shape": "rectangle", "size": [4, 4], "material": "floor"},
    {"name": "spinner", "shape": "sphere", "radius": 0.5, "material": "metal",
     "transform": {"translate": [1, 0.5, 0]},
     "motion": {"rotate": {"axis": [0, 1, 0], "degrees": 90}}},
    {"shape": "torus", "major_radius": 1, "minor_radius": 0.2, "material": "glass"},
    {"shape": "disk", "radius": 0.3, "material": "lamp", "transform": {"translate": [0, 3, 0], "rotate": [180, 1, 0, 0]}}]
})";

TEST(SceneLoader, ValidSceneLoadsEveryField) {
  const Scene s = parseSceneJson(kValid, "valid.json", ".");
  EXPECT_EQ(s.settings.width, 64);
  EXPECT_EQ(s.settings.height, 32);
  EXPECT_EQ(s.settings.spp, 8);
  EXPECT_EQ(s.settings.maxDepth, 5);
  EXPECT_FLOAT_EQ(s.camera.lensRadius, 0.1f);
  EXPECT_FLOAT_EQ(s.camera.shutterOpen, 0.2f);
  ASSERT_TRUE(s.background.has_value());
  EXPECT_FLOAT_EQ(s.background->z, 0.3f);
  ASSERT_EQ(s.materials.size(), 4u);
  EXPECT_EQ(s.materials[0].albedoTexture, 0);
  EXPECT_EQ(s.materials[1].type, Material::Type::Conductor);
  EXPECT_EQ(s.materials[2].type, Material::Type::Dielectric);
  EXPECT_TRUE(s.materials[3].isEmissive());
  ASSERT_EQ(s.meshes.size(), 4u);
  EXPECT_EQ(s.meshes[1].name, "spinner");
  EXPECT_EQ(s.meshes[1].timeSteps, 19);  // 90 degrees at 5 degrees per step, plus one
  EXPECT_EQ(s.meshes[0].timeSteps, 1);
}

std::string withReplaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

struct BadCase {
  std::string from, to, expected;
};

TEST(SceneLoader, EachMalformedFieldIsNamed) {
  const std::vector<BadCase> cases = {
      {R"("width": 64)", R"("width": -3)", "render.width: value -3 outside"},
      {R"("spp": 8)", R"("spp": "many")", "render.spp: expected an integer"},
      {R"("fov": 30)", R"("fov": 200)", "camera.fov"},
      {R"("fov": 30)", R"("fov": 30, "orthographic_height": -2)", "camera.orthographic_height"},
      {R"("eye": [0, 1, 4])", R"("eye": [0, 1])", "camera.eye: expected [x, y, z]"},
      {R"("eye": [0, 1, 4])", R"("eye": [0, "one", 4])", "camera.eye[1]: expected a number"},
      {R"("shutter": [0.2, 0.8])", R"("shutter": [0.9, 0.1])", "camera.shutter"},
      {R"("look_at": [0, 0, 0])", R"("look_at": [0, 1, 4])", "camera: eye and look_at coincide"},
      {R"("roughness": 0.4)", R"("roughness": 1.4)", "materials.metal.roughness"},
      {R"("type": "conductor")", R"("type": "plastic")",
       "materials.metal.type: unknown material type 'plastic'"},
      {R"("albedo": "check")", R"("albedo": "chekc")",
       "materials.floor.albedo: unknown texture 'chekc'"},
      {R"("ior": 1.33)", R"("ior": 0)", "materials.glass.ior: expected a positive number"},
      {R"("material": "metal")", R"("material": "chrome")",
       "objects[1].material: unknown material 'chrome'"},
      {R"("radius": 0.5)", R"("radius": -0.5)", "objects[1].radius: expected a positive number"},
      {R"("radius": 0.5)", R"("radus": 0.5)", "objects[1].radus: unknown field"},
      {R"("shape": "torus")", R"("shape": "teapot")", "objects[2].shape: unknown shape 'teapot'"},
      {R"("degrees": 90)", R"("degrees": "fast")",
       "objects[1].motion.rotate.degrees: expected a number"},
      {R"("translate": [1, 0.5, 0])", R"("translate": [1, 0.5, 1e999])", "test.json"},
      {R"("scale": [4, 4])", R"("scale": [4, -4])", "textures.check.scale"},
      {R"("type": "checker")", R"("type": "image", "file": "nowhere.png")",
       "textures.check.file: cannot open"},
      {R"("background": [0.1, 0.2, 0.3])", R"("background": [0.1, -0.2, 0.3])", "background"},
      {R"("render")", R"("rendr")", "rendr: unknown field"},
  };
  for (const BadCase& c : cases) {
    const std::string text = withReplaced(kValid, c.from, c.to);
    try {
      parseSceneJson(text, "test.json", ".");
      ADD_FAILURE() << "no error for " << c.to;
    } catch (const SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("test.json"), std::string::npos) << what;
      EXPECT_NE(what.find(c.expected), std::string::npos)
          << "expected '" << c.expected << "' in: " << what;
    }
  }
}

// A light's range: read for point and spot lights, an error for a negative one and for a
// directional light (which has none), named by the light.
TEST(SceneLoader, ALightsRangeIsReadOrItsErrorNamed) {
  const auto scene = [](const std::string& light) {
    return R"({"camera": {"eye": [0, 1, 4], "look_at": [0, 0, 0]},
               "materials": {"m": {"type": "diffuse", "albedo": 0.5}},
               "objects": [{"shape": "sphere", "radius": 1, "material": "m"}],
               "lights": [)" +
           light + "]}";
  };
  EXPECT_EQ(
      parseSceneJson(scene(R"({"type": "point", "range": 3})"), "test.json", ".").lights[0].range,
      3.0f);
  EXPECT_EQ(parseSceneJson(scene(R"({"type": "spot"})"), "test.json", ".").lights[0].range, 0.0f);
  for (const char* bad :
       {R"({"type": "point", "range": -1})", R"({"type": "directional", "range": 3})"}) {
    try {
      parseSceneJson(scene(bad), "test.json", ".");
      ADD_FAILURE() << "no error for " << bad;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find("test.json: lights[0].range"), std::string::npos)
          << e.what();
    }
  }
}

// Found by the scene fuzzer: a rotation axis with a component near 1e24 overflowed a float's
// squared length, and the object's placement threw an exception that was not a SceneError.
TEST(SceneLoader, HugeRotationAxesAreNormalisedAndBadTransformsAreSceneErrors) {
  const auto scene = [](const std::string& object) {
    return R"({"materials": {"m": {"type": "diffuse"}}, "objects": [)" + object + "]}";
  };
  const Scene s = parseSceneJson(
      scene(R"({"shape": "rectangle", "material": "m", "transform": {"rotate": [180, 1, 1e24, 0]},
                "motion": {"rotate": {"axis": [1e24, 0, 0], "degrees": 90}}})"),
      "huge_axis.json", ".");
  // Half a turn about y turns the rectangle's +y normal... not at all: it stays +y.
  ASSERT_FALSE(s.meshes[0].normals.empty());
  EXPECT_NEAR(s.meshes[0].normals[0].y, 1.0f, 1e-5f);
  try {
    parseSceneJson(scene(R"({"shape": "rectangle", "material": "m",
                             "transform": {"scale": [1e-30, 1e-30, 1e-30]}})"),
                   "tiny.json", ".");
    FAIL() << "a singular transform must be refused";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("tiny.json: objects[0].transform"), std::string::npos)
        << e.what();
  }
}

TEST(SceneLoader, SyntaxErrorsGiveLineAndColumn) {
  try {
    parseSceneJson("{\n  \"render\": {\"width\": 4,,}\n}", "broken.json", ".");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("broken.json:2:"), std::string::npos) << e.what();
  }
}

TEST(SceneLoader, MissingFilesAreNamed) {
  EXPECT_THROW(
      {
        try {
          loadScene("/nonexistent/scene.json");
        } catch (const SceneError& e) {
          EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.json"), std::string::npos);
          throw;
        }
      },
      SceneError);
  const std::string text =
      withReplaced(kValid, R"("shape": "torus", "major_radius": 1, "minor_radius": 0.2)",
                   R"("shape": "mesh", "file": "missing.ply")");
  try {
    parseSceneJson(text, "test.json", "/tmp");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("objects[2].file: cannot open '/tmp/missing.ply'"),
              std::string::npos)
        << e.what();
  }
}

TEST(SceneLoader, ObjFileIsASceneWithAFramedCamera) {
  const std::string obj = test::outputPath("quad_scene.obj");
  {
    std::ofstream f(obj);
    f << "v -1 0 -1\nv 1 0 -1\nv 1 0 1\nv -1 0 1\nf 1 3 2\nf 1 4 3\n";
  }
  const Scene s = loadScene(obj);
  ASSERT_EQ(s.meshes.size(), 1u);
  EXPECT_EQ(s.meshes[0].triangleCount(), 2u);
  EXPECT_GT(s.camera.eye.z, 1.0f);
  EXPECT_NEAR(glm::length(s.camera.lookAt), 0.0f, 1e-5f);
}

TEST(SceneLoader, ShippedScenesLoad) {
  for (const char* name : {"cornell", "balls", "tire", "stairs", "dragon"}) {
    const std::string path = test::sourcePath(std::string("scenes/") + name + ".json");
    EXPECT_NO_THROW(loadScene(path)) << path;
  }
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// The example in docs/scene-format.md is a real scene: keep the documentation true.
TEST(SceneLoader, DocumentedExampleLoads) {
  std::ifstream doc(test::sourcePath("docs/scene-format.md"));
  std::stringstream text;
  text << doc.rdbuf();
  const std::string md = text.str();
  const size_t heading = md.find("## Example");
  ASSERT_NE(heading, std::string::npos);
  const size_t start = md.find("```json\n", heading);
  const size_t end = md.find("```", start + 8);
  ASSERT_NE(start, std::string::npos);
  const Scene scene = parseSceneJson(md.substr(start + 8, end - start - 8), "scene-format.md", ".");
  EXPECT_EQ(scene.meshes.size(), 4u);
  EXPECT_EQ(scene.meshes[1].timeSteps, 37);
}

}  // namespace
}  // namespace penumbra
