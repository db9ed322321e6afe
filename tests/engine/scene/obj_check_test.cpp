// Strict OBJ / MTL checks: every malformed number, index or count is an error that names the
// file, the line and the field; well-formed files (comments, CRLF, '+' signs, long polygons,
// relative indices) pass. loadObj runs the checks on the OBJ and on the MTL libraries it
// finds.
#include "scene/obj_check.h"

#include "scene/mesh_io.h"
#include "scene/scene.h"
#include "tests/engine/scene/expect_scene_error.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <initializer_list>
#include <string>

namespace penumbra {
namespace {

using test::expectSceneError;

void expectObjError(const std::string& text, std::initializer_list<std::string> parts) {
  expectSceneError([&] { checkObjText(text, "m.obj"); }, parts);
}

void expectMtlError(const std::string& text, std::initializer_list<std::string> parts) {
  expectSceneError([&] { checkMtlText(text, "m.mtl"); }, parts);
}

TEST(ObjCheck, WellFormedTextPasses) {
  const std::string obj =
      "# a comment\r\n"
      "mtllib a.mtl b.mtl\r\n"
      "o thing\ng group\ns off\ns 1\n"
      "v 0 0 0\nv +1 0 0 # trailing comment\nv 1 1e-3 -1.5E+2 1\nv 0 1 0 0.5 0.5 0.5\n"
      "vt 0\nvt 0 1\nvt 0 1 0\nvn 0 0 1\n"
      "usemtl red\n"
      "f 1 2 3\nf 1/1 2/2 3/3\nf 1//1 2//1 3//1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n"
      "f -4 -3 -2 -1\nl 1 2 3\np 4\n"
      "curv2 1 2 3\n";  // statements it does not know are left alone
  EXPECT_EQ(checkObjText(obj, "m.obj"), (std::vector<std::string>{"a.mtl", "b.mtl"}));

  // A polygon of many corners (a cylinder's cap) is fine.
  std::string cap;
  for (int i = 0; i < 40; ++i) cap.append("v ").append(std::to_string(i)).append(" 0 0\n");
  cap += "f";
  for (int i = 1; i <= 40; ++i) cap.append(" ").append(std::to_string(i));
  cap += "\n";
  EXPECT_NO_THROW(checkObjText(cap, "cap.obj"));
  EXPECT_NO_THROW(checkObjText("", "empty.obj"));
}

TEST(ObjCheck, MalformedNumbersNameLineAndField) {
  expectObjError("v 0 0 0\nv 0 zero 0\n", {"m.obj:2:", "'v' y", "'zero'", "not a number"});
  expectObjError("v 1 2 3x\n", {"m.obj:1:", "'v' z", "'3x'"});
  expectObjError("v nan 0 0\n", {"m.obj:1:", "'v' x", "not a finite number"});
  expectObjError("v 0 inf 0\n", {"'v' y", "not a finite number"});
  expectObjError("v 0 0 1e39\n", {"'v' z", "not a finite number"});  // beyond float
  expectObjError("v 0 0 1e999\n", {"'v' z", "out of range"});
  expectObjError("vn 0 0\n", {"m.obj:1:", "'vn' needs 3 numbers, got 2"});
  expectObjError("vt 0 0 0 0\n", {"'vt' needs 1 to 3 numbers, got 4"});
  expectObjError("v 0 0\n", {"'v' needs 3 to 7 numbers, got 2"});
  expectObjError("vt 0.5 --1\n", {"'vt' v", "'--1'"});
  expectObjError("v 0 0 0 1 2 3 4 5\n", {"got 8"});
}

TEST(ObjCheck, MalformedIndicesNameLineAndCorner) {
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  expectObjError(tri + "f 1 2\n", {"m.obj:6:", "'f' needs at least 3 vertices, got 2"});
  expectObjError(tri + "f 1 two 3\n", {"m.obj:6:", "corner 2", "vertex index", "'two'"});
  expectObjError(tri + "f 1 2 0\n", {"corner 3", "OBJ indices start at 1"});
  expectObjError(tri + "f 1/x 2 3\n", {"corner 1", "texcoord index", "'x'"});
  expectObjError(tri + "f 1/1/ 2 3\n", {"corner 1", "empty normal index"});
  expectObjError(tri + "f 1/ 2 3\n", {"corner 1", "empty texcoord index"});
  expectObjError(tri + "f 1/1/1/1 2 3\n", {"corner 1", "more than three indices"});
  expectObjError(tri + "f -1 -2 -4\n",
                 {"corner 3", "-4 reaches before the first vertex", "3 defined so far"});
  expectObjError(tri + "f 1//-2 2 3\n", {"normal index -2", "1 defined so far"});
  expectObjError(tri + "f 1 2 -9223372036854775808\n", {"corner 3", "reaches before"});
  expectObjError(tri + "f 1 2 99999999999999999999\n", {"corner 3", "not an integer"});
  expectObjError(tri + "l 1\n", {"'l' needs at least 2 vertices"});
  expectObjError(tri + "s maybe\n", {"'s' needs one group number or 'off'"});
  expectObjError("mtllib\n", {"m.obj:1:", "'mtllib' needs a file name"});
  expectObjError("usemtl # no name\n", {"'usemtl' needs a material name"});
}

TEST(ObjCheck, MtlNumbers) {
  EXPECT_NO_THROW(
      checkMtlText("# lib\nnewmtl a\nKa 0 0 0\nKd 0.5 0.5 0.5\nKs 1 1 1\nKe 0 0 0\n"
                   "Tf 1 1 1\nNs 10\nNi 1.5\nd 1\nTr 0\nillum 2\nmap_Kd a b.png\n"
                   "newmtl b\nKd 1 1 1\n",
                   "m.mtl"));
  expectMtlError("newmtl a\nKd 1 x 1\n", {"m.mtl:2:", "'Kd' g", "'x'"});
  expectMtlError("newmtl a\nKd 1 1\n", {"m.mtl:2:", "'Kd' needs 3 numbers, got 2"});
  expectMtlError("newmtl a\nNs\n", {"'Ns' needs 1 numbers, got 0"});
  expectMtlError("newmtl a\nNi 1.5.2\n", {"'Ni' field 1", "'1.5.2'"});
  expectMtlError("newmtl a\nillum 11\n", {"m.mtl:2:", "'illum' needs one integer in [0, 10]"});
  expectMtlError("newmtl a\nillum 2.5\n", {"'illum'"});
  expectMtlError("Kd 1 1 1\n", {"m.mtl:1:", "'Kd' before the first 'newmtl'"});
  expectMtlError("newmtl\n", {"'newmtl' needs a material name"});
}

TEST(ObjCheck, LoadObjChecksTheObjAndItsMtl) {
  const std::string badVertex =
      test::writeOutput("obj_check/bad_vertex.obj", "v 0 0 0\nv 0 zero 0\nv 1 0 0\nf 1 2 3\n");
  expectSceneError([&] { loadObj(badVertex); }, {"bad_vertex.obj:2:", "'v' y", "'zero'"});

  test::writeOutput("obj_check/bad.mtl", "newmtl red\nKd 1 0 0\nNs ten\n");
  const std::string badMtl = test::writeOutput(
      "obj_check/bad_mtl.obj", "mtllib bad.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl red\nf 1 2 3\n");
  expectSceneError([&] { loadObj(badMtl); }, {"bad.mtl:3:", "'Ns'", "'ten'"});

  // A good file still loads, and a missing library still falls back to the default.
  const std::string good = test::writeOutput(
      "obj_check/good.obj", "mtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  EXPECT_EQ(loadObj(good).mesh.indices.size(), 3u);
}

}  // namespace
}  // namespace penumbra
