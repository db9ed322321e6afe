// Strict checks of Wavefront OBJ and MTL text, run before tinyobjloader parses the files.
// tinyobjloader reads a malformed number as 0 (`v 0 zero 0` is a vertex at the origin) and a
// malformed index as some other index, silently; these checks turn such lines into a
// SceneError that names the file, the line and the field.
//
// What is checked, statement by statement (others, and comments, are left alone):
//   OBJ: v (3 to 7 finite numbers: x y z, then w or an r g b colour), vn (3), vt (1 to 3);
//        f (at least 3 corners), l (2), p (1): each corner v, v/vt, v//vn or v/vt/vn, every
//        index a non-zero integer, a negative (relative) one no further back than the
//        elements defined so far; s (off or an integer); mtllib and usemtl need a name.
//   MTL: newmtl needs a name; Ka Kd Ks Ke Tf 3 finite numbers; Ns Ni d Tr 1; illum an
//        integer in [0, 10]; a statement before the first newmtl is an error.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace penumbra {

// Throws SceneError("FILE:LINE: ...") at the first bad statement of `text`, read from `file`.
// Returns the names given to mtllib, in order.
std::vector<std::string> checkObjText(std::string_view text, const std::string& file);

// The same for an MTL library.
void checkMtlText(std::string_view text, const std::string& file);

}  // namespace penumbra
