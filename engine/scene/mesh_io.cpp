// Mesh file readers. PLY is parsed here directly (header, then ASCII tokens or
// binary values in either byte order); OBJ/MTL parsing is tinyobjloader's, after the strict
// checks of obj_check.cpp, and this file turns its output into a penumbra Mesh and Materials.
#include "scene/mesh_io.h"

#include "scene/obj_check.h"

#include <tiny_obj_loader.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string_view>
#include <unordered_map>

namespace penumbra {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fileError(const std::string& file, const std::string& message) {
  throw SceneError(file + ": " + message);
}

// Indices are printed as plain integers even when they came from a float property.
std::string numberText(double value) {
  std::ostringstream text;
  text << std::setprecision(15) << value;
  return text.str();
}

void requireReadableFile(const std::string& path) {
  std::error_code error;
  if (!fs::exists(path, error)) fileError(path, "cannot open file");
  if (fs::is_directory(path, error)) fileError(path, "is a directory, not a file");
}

std::string readWholeFile(const std::string& path) {
  requireReadableFile(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) fileError(path, "cannot open file");
  std::ostringstream contents;
  contents << in.rdbuf();
  if (in.bad()) fileError(path, "read error");
  return std::move(contents).str();
}

}  // namespace

// Zero or non-finite normals are replaced by the normalised sum of the area-weighted
// geometric normals of the triangles around the vertex, so shading stays smooth instead of
// turning NaN.
void repairNormals(Mesh& mesh) {
  if (mesh.normals.empty()) return;
  std::vector<char> missing(mesh.vertexCount, 0);
  bool anyMissing = false;
  for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
    const float length = glm::length(mesh.normals[v]);
    missing[v] = !(length > 0.0f && std::isfinite(length));
    anyMissing = anyMissing || missing[v];
    if (!missing[v]) mesh.normals[v] /= length;
  }
  if (!anyMissing) return;
  std::vector<vec3> sums(mesh.vertexCount, vec3(0.0f));
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1], c = mesh.indices[t + 2];
    const vec3 n =
        glm::cross(mesh.positions[b] - mesh.positions[a], mesh.positions[c] - mesh.positions[a]);
    for (uint32_t v : {a, b, c}) sums[v] += n;
  }
  for (uint32_t v = 0; v < mesh.vertexCount; ++v) {
    const float length = glm::length(sums[v]);
    // A vertex only on degenerate triangles is never shaded; any unit vector will do.
    if (missing[v]) mesh.normals[v] = length > 0.0f ? sums[v] / length : vec3(0, 0, 1);
  }
}

namespace {

// ---------------------------------------------------------------------------- PLY

enum class PlyFormat { Ascii, BinaryLittleEndian, BinaryBigEndian };

// A PLY scalar type: all a reader needs is its size and how to interpret its bits.
struct PlyType {
  uint8_t size = 4;
  bool isFloat = true;
  bool isSigned = true;
};

bool parsePlyType(std::string_view name, PlyType& type) {
  struct Named {
    std::string_view name, alias;
    PlyType type;
  };
  static constexpr Named kTypes[] = {
      {"char", "int8", {1, false, true}},    {"uchar", "uint8", {1, false, false}},
      {"short", "int16", {2, false, true}},  {"ushort", "uint16", {2, false, false}},
      {"int", "int32", {4, false, true}},    {"uint", "uint32", {4, false, false}},
      {"float", "float32", {4, true, true}}, {"double", "float64", {8, true, true}}};
  for (const Named& named : kTypes) {
    if (named.name == name || named.alias == name) {
      type = named.type;
      return true;
    }
  }
  return false;
}

struct PlyProperty {
  std::string name;
  PlyType type;  // the item type for a list
  bool isList = false;
  PlyType countType;
};

struct PlyElement {
  std::string name;
  uint64_t count = 0;
  std::vector<PlyProperty> properties;

  int find(std::string_view propertyName) const {
    for (size_t i = 0; i < properties.size(); ++i) {
      if (properties[i].name == propertyName) return int(i);
    }
    return -1;
  }
};

struct PlyHeader {
  PlyFormat format = PlyFormat::Ascii;
  std::vector<PlyElement> elements;
  size_t dataStart = 0;  // byte offset just past the end_header line
  int dataLine = 0;      // line number of the first data line (ASCII messages)
};

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isSpace(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !isSpace(line[i])) ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
  return words;
}

PlyHeader parsePlyHeader(const std::string& file, const std::string& data) {
  PlyHeader header;
  bool haveFormat = false;
  size_t pos = 0;
  int lineNumber = 0;
  const auto lineError = [&](const std::string& message) {
    fileError(file, "line " + std::to_string(lineNumber) + ": " + message);
  };
  const auto readType = [&](std::string_view name) {
    PlyType type;
    if (!parsePlyType(name, type)) lineError("unknown property type '" + std::string(name) + "'");
    return type;
  };

  for (;;) {
    if (pos >= data.size()) fileError(file, "the header has no end_header line");
    size_t end = data.find('\n', pos);
    if (end == std::string::npos) end = data.size();
    const std::vector<std::string_view> words =
        splitWords(std::string_view(data).substr(pos, end - pos));
    pos = std::min(end + 1, data.size());
    ++lineNumber;

    if (lineNumber == 1) {
      if (words.size() != 1 || words[0] != "ply") fileError(file, "not a PLY file (no 'ply' line)");
      continue;
    }
    if (words.empty() || words[0] == "comment" || words[0] == "obj_info") continue;
    const std::string_view keyword = words[0];
    if (keyword == "end_header") break;

    if (keyword == "format") {
      if (words.size() != 3) lineError("expected 'format <kind> 1.0'");
      const std::string_view formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
      const auto known = std::find(std::begin(formats), std::end(formats), words[1]);
      if (known == std::end(formats)) lineError("unknown format '" + std::string(words[1]) + "'");
      header.format = PlyFormat(known - std::begin(formats));  // same order as the enum
      haveFormat = true;
    } else if (keyword == "element") {
      if (words.size() != 3) lineError("expected 'element <name> <count>'");
      PlyElement element;
      element.name = words[1];
      const std::string_view count = words[2];
      const auto [end, error] =
          std::from_chars(count.data(), count.data() + count.size(), element.count);
      if (error != std::errc() || end != count.data() + count.size()) {
        lineError("bad element count '" + std::string(count) + "'");
      }
      for (const PlyElement& other : header.elements) {
        if (other.name == element.name) lineError("duplicate element '" + element.name + "'");
      }
      header.elements.push_back(std::move(element));
    } else if (keyword == "property") {
      if (header.elements.empty()) lineError("property before any element");
      PlyProperty property;
      if (words.size() >= 2 && words[1] == "list") {
        if (words.size() != 5)
          lineError("expected 'property list <count type> <item type> <name>'");
        property.isList = true;
        property.countType = readType(words[2]);
        if (property.countType.isFloat) {
          lineError("list count type '" + std::string(words[2]) + "' is not an integer type");
        }
        property.type = readType(words[3]);
        property.name = words[4];
      } else {
        if (words.size() != 3) lineError("expected 'property <type> <name>'");
        property.type = readType(words[1]);
        property.name = words[2];
      }
      header.elements.back().properties.push_back(std::move(property));
    } else {
      lineError("unknown header keyword '" + std::string(keyword) + "'");
    }
  }
  if (!haveFormat) fileError(file, "the header has no format line");
  header.dataStart = pos;
  header.dataLine = lineNumber + 1;
  return header;
}

// Every element needs a minimum number of bytes (binary: its scalars and list
// counts; ASCII: a character and a separator per value), so a header declaring
// more elements than the rest of the file can hold is corrupt. Rejecting it here
// keeps a damaged count from making us reserve gigabytes.
void checkCountsFitFile(const std::string& file, const PlyHeader& header, uint64_t dataBytes) {
  const bool ascii = header.format == PlyFormat::Ascii;
  // The last ASCII value of the file may lack its trailing separator.
  const uint64_t budget = ascii ? dataBytes + 1 : dataBytes;
  uint64_t needed = 0;
  for (const PlyElement& element : header.elements) {
    uint64_t perEntry = 0;
    for (const PlyProperty& property : element.properties) {
      perEntry += ascii ? 2 : (property.isList ? property.countType : property.type).size;
    }
    if (perEntry == 0) continue;
    if (element.count > (budget - needed) / perEntry) {
      fileError(file, "element '" + element.name + "' declares " + std::to_string(element.count) +
                          " entries, more than the " + std::to_string(dataBytes) +
                          " bytes of data can hold");
    }
    needed += element.count * perEntry;
  }
}

// Reads the values of the data section one at a time, as doubles (exact for every
// PLY integer type), in the file's format.
class PlyValueReader {
 public:
  PlyValueReader(const std::string& file, const std::string& data, const PlyHeader& header)
      : file_(file),
        begin_(data.data()),
        cursor_(data.data() + header.dataStart),
        end_(data.data() + data.size()),
        format_(header.format),
        line_(header.dataLine) {}

  void setElement(const PlyElement& element) { element_ = &element; }

  double read(PlyType type) {
    return format_ == PlyFormat::Ascii ? readAscii(type) : readBinary(type);
  }

  // Reads a list's length and checks that the rest of the file could hold that
  // many items, before anyone loops over a corrupt, enormous length.
  uint64_t readListLength(const PlyProperty& property) {
    const double length = read(property.countType);
    if (length < 0) error("negative list length " + numberText(length));
    const uint64_t count = uint64_t(length);
    // Same minimum sizes as checkCountsFitFile: bytes per item, or for ASCII a
    // character and a separator (the very last one may be missing).
    const bool ascii = format_ == PlyFormat::Ascii;
    const uint64_t available = uint64_t(end_ - cursor_) + (ascii ? 1 : 0);
    if (count > available / (ascii ? 2 : property.type.size)) truncated();
    return count;
  }

  [[noreturn]] void error(const std::string& message) const {
    if (format_ == PlyFormat::Ascii) {
      fileError(file_, "line " + std::to_string(line_) + ": " + message);
    }
    fileError(file_, "element '" + element_->name + "': " + message);
  }

 private:
  [[noreturn]] void truncated() const {
    if (format_ == PlyFormat::Ascii) {
      error("unexpected end of file in element '" + element_->name + "'");
    }
    fileError(file_, "truncated binary data in element '" + element_->name + "' at byte " +
                         std::to_string(cursor_ - begin_) + " of " + std::to_string(end_ - begin_));
  }

  double readBinary(PlyType type) {
    const size_t size = type.size;
    if (size_t(end_ - cursor_) < size) truncated();
    // Assemble the value from its bytes in the file's order, so the host's own
    // byte order never matters.
    uint64_t bits = 0;
    for (size_t i = 0; i < size; ++i) {
      const size_t byte = format_ == PlyFormat::BinaryLittleEndian ? size - 1 - i : i;
      bits = (bits << 8) | uint8_t(cursor_[byte]);
    }
    cursor_ += size;
    if (type.isFloat) {
      return size == 4 ? double(std::bit_cast<float>(uint32_t(bits))) : std::bit_cast<double>(bits);
    }
    if (type.isSigned) {
      // Move the sign bit to the top; the arithmetic shift back sign-extends.
      const int unused = 64 - 8 * int(size);
      return double(int64_t(bits << unused) >> unused);
    }
    return double(bits);
  }

  double readAscii(PlyType type) {
    while (cursor_ != end_ && isSpace(*cursor_)) {
      if (*cursor_ == '\n') ++line_;
      ++cursor_;
    }
    if (cursor_ == end_) truncated();
    const char* start = cursor_;
    while (cursor_ != end_ && !isSpace(*cursor_)) ++cursor_;
    // from_chars is locale-independent but rejects an explicit '+'.
    const char* first = (*start == '+' && cursor_ - start > 1) ? start + 1 : start;
    double value = 0.0;
    const auto [end, failure] = std::from_chars(first, cursor_, value);
    if (failure == std::errc() && end == cursor_ && (type.isFloat || value == std::floor(value))) {
      return value;
    }
    error(std::string("expected ") + (type.isFloat ? "a number" : "an integer") + " in element '" +
          element_->name + "', got '" + std::string(start, cursor_) + "'");
  }

  const std::string& file_;
  const char* begin_;
  const char* cursor_;
  const char* end_;
  PlyFormat format_;
  int line_;
  const PlyElement* element_ = nullptr;
};

// Index of a scalar property; -1 when it is absent, or an error if `required`.
int findScalar(const std::string& file, const PlyElement& element, std::string_view name,
               bool required = false) {
  const int index = element.find(name);
  if (index >= 0 && element.properties[index].isList) {
    fileError(file, "property '" + std::string(name) + "' of element '" + element.name +
                        "' is a list, expected a number");
  }
  if (index < 0 && required) {
    fileError(file, "element '" + element.name + "' has no property '" + std::string(name) + "'");
  }
  return index;
}

}  // namespace

Mesh loadPly(const std::string& path) {
  const std::string data = readWholeFile(path);
  const PlyHeader header = parsePlyHeader(path, data);
  checkCountsFitFile(path, header, data.size() - header.dataStart);

  const PlyElement* vertexElement = nullptr;
  const PlyElement* faceElement = nullptr;
  for (const PlyElement& element : header.elements) {
    if (element.name == "vertex") vertexElement = &element;
    if (element.name == "face") faceElement = &element;
  }
  if (!vertexElement) fileError(path, "no element 'vertex'");
  if (!faceElement) fileError(path, "no element 'face' (point clouds cannot be rendered)");
  if (vertexElement->count > std::numeric_limits<uint32_t>::max()) {
    fileError(path, "too many vertices (" + std::to_string(vertexElement->count) + ")");
  }

  const PlyElement& vertices = *vertexElement;
  const int x = findScalar(path, vertices, "x", true), y = findScalar(path, vertices, "y", true);
  const int z = findScalar(path, vertices, "z", true);
  const int nx = findScalar(path, vertices, "nx"), ny = findScalar(path, vertices, "ny");
  const int nz = findScalar(path, vertices, "nz");
  const bool hasNormals = nx >= 0 && ny >= 0 && nz >= 0;
  int u = -1, v = -1;
  for (const auto& [uName, vName] :
       {std::pair{"u", "v"}, std::pair{"s", "t"}, std::pair{"texture_u", "texture_v"},
        std::pair{"texture_s", "texture_t"}}) {
    u = findScalar(path, vertices, uName);
    v = findScalar(path, vertices, vName);
    if (u >= 0 && v >= 0) break;
  }
  const bool hasUvs = u >= 0 && v >= 0;
  int faceIndices = faceElement->find("vertex_indices");
  if (faceIndices < 0) faceIndices = faceElement->find("vertex_index");
  if (faceIndices < 0 || !faceElement->properties[faceIndices].isList) {
    fileError(path, "element 'face' has no list property 'vertex_indices'");
  }

  Mesh mesh;
  mesh.name = fs::path(path).stem().string();
  mesh.vertexCount = uint32_t(vertexElement->count);
  mesh.positions.reserve(mesh.vertexCount);
  if (hasNormals) mesh.normals.reserve(mesh.vertexCount);
  if (hasUvs) mesh.uvs.reserve(mesh.vertexCount);
  mesh.indices.reserve(faceElement->count * 3);

  PlyValueReader reader(path, data, header);
  std::vector<double> values;
  std::vector<uint32_t> polygon;
  for (const PlyElement& element : header.elements) {
    reader.setElement(element);
    const bool isVertex = &element == vertexElement, isFace = &element == faceElement;
    values.assign(element.properties.size(), 0.0);
    // An element without properties occupies no bytes however large its count.
    const uint64_t count = element.properties.empty() ? 0 : element.count;
    for (uint64_t entry = 0; entry < count; ++entry) {
      for (size_t k = 0; k < element.properties.size(); ++k) {
        const PlyProperty& property = element.properties[k];
        if (!property.isList) {
          values[k] = reader.read(property.type);
          continue;
        }
        const uint64_t length = reader.readListLength(property);
        const bool isPolygon = isFace && int(k) == faceIndices;
        if (isPolygon) polygon.clear();
        for (uint64_t item = 0; item < length; ++item) {
          const double value = reader.read(property.type);
          if (!isPolygon) continue;
          if (!(value >= 0 && value < double(mesh.vertexCount)) || value != std::floor(value)) {
            fileError(path, "face " + std::to_string(entry) + ": vertex index " +
                                numberText(value) + " out of range (" +
                                std::to_string(mesh.vertexCount) + " vertices)");
          }
          polygon.push_back(uint32_t(value));
        }
      }
      if (isVertex) {
        const vec3 position(values[x], values[y], values[z]);
        if (!std::isfinite(position.x) || !std::isfinite(position.y) ||
            !std::isfinite(position.z)) {
          fileError(path, "vertex " + std::to_string(entry) + ": position is not finite");
        }
        mesh.positions.push_back(position);
        if (hasNormals) mesh.normals.emplace_back(values[nx], values[ny], values[nz]);
        if (hasUvs) mesh.uvs.emplace_back(values[u], values[v]);
      } else if (isFace) {
        // Fan triangulation keeps the polygon's winding; polygons of fewer than
        // three corners (lines, points) have no area and are dropped.
        for (size_t corner = 2; corner < polygon.size(); ++corner) {
          mesh.indices.insert(mesh.indices.end(),
                              {polygon[0], polygon[corner - 1], polygon[corner]});
        }
      }
    }
  }
  if (mesh.indices.empty()) fileError(path, "no triangles");
  mesh.materialIds.assign(mesh.triangleCount(), 0);
  repairNormals(mesh);
  return mesh;
}

// ---------------------------------------------------------------------------- OBJ

Material materialFromMtl(const ObjMaterialDesc& desc) {
  Material material;
  material.name = desc.name;
  const float specularMax = std::max({desc.specular.x, desc.specular.y, desc.specular.z});
  const bool emissive = desc.emission.x > 0 || desc.emission.y > 0 || desc.emission.z > 0;
  const bool refractiveIllum = desc.illum == 4 || desc.illum == 6 || desc.illum == 7;

  if (emissive) {
    // An area light: emits Ke from its front side and reflects like a diffuse Kd.
    material.type = Material::Type::Diffuse;
    material.albedo = desc.diffuse;
    material.emission = desc.emission;
  } else if (desc.dissolve < 1.0f || (refractiveIllum && desc.ior > 1.0f)) {
    material.type = Material::Type::Dielectric;
    // Exporters often leave Ni at its default 1 on glass; an index of 1 would make
    // the object invisible, so fall back to ordinary glass.
    material.ior = desc.ior > 1.0f ? desc.ior : 1.5f;
  } else if (specularMax > 0 &&
             (desc.shininess >= 1000.0f || (desc.illum == 3 && specularMax >= 0.5f))) {
    material.type = Material::Type::Mirror;
    material.albedo = desc.specular;
  } else if (specularMax > 0) {
    material.type = Material::Type::Conductor;
    material.albedo = desc.specular;
    // Ns is a Phong exponent. Matching the Phong lobe to a microfacet distribution
    // (Walter et al. 2007, "Microfacet models for refraction") gives the
    // distribution width alpha = sqrt(2 / (Ns + 2)). Material::roughness is the
    // perceptual parameter with alpha = roughness², hence
    //   roughness = sqrt(alpha) = (2 / (Ns + 2))^(1/4).
    const float alpha = std::sqrt(2.0f / (std::max(desc.shininess, 0.0f) + 2.0f));
    material.roughness = std::clamp(std::sqrt(alpha), 0.02f, 1.0f);
  } else {
    material.type = Material::Type::Diffuse;
    material.albedo = desc.diffuse;
  }
  return material;
}

namespace {

vec3 toVec3(const tinyobj::real_t* values) { return vec3(values[0], values[1], values[2]); }

// map_Kd as written in the MTL, made usable from the current directory: relative
// to the OBJ's folder (where tinyobjloader looks for the MTL), with Windows
// separators accepted.
std::string resolveTexturePath(const fs::path& objFolder, std::string name) {
  if (name.empty()) return {};
  std::replace(name.begin(), name.end(), '\\', '/');
  const fs::path texture(name);
  if (texture.is_absolute()) return texture.lexically_normal().string();
  return (objFolder / texture).lexically_normal().string();
}

std::string firstLineContaining(const std::string& text, std::string_view needle) {
  const size_t at = text.find(needle);
  if (at == std::string::npos) return {};
  const size_t from = text.rfind('\n', at) + 1;  // npos + 1 == 0: the first line
  return text.substr(from, text.find('\n', at) - from);
}

struct CornerKey {
  int position, texcoord, normal;
  bool operator==(const CornerKey&) const = default;
};

struct CornerKeyHash {
  size_t operator()(const CornerKey& key) const {
    uint64_t h = uint32_t(key.position);
    h = h * 0x9E3779B97F4A7C15ull ^ uint32_t(key.texcoord);
    h = h * 0x9E3779B97F4A7C15ull ^ uint32_t(key.normal);
    return size_t(h ^ (h >> 29));
  }
};

}  // namespace

ObjData loadObj(const std::string& path) {
  // tinyobjloader reads a malformed number as 0 and goes on; check the text first.
  const fs::path objFolder = fs::path(path).parent_path();
  std::vector<std::string> libraries, warnings;
  for (const std::string& library : checkObjText(readWholeFile(path), path)) {
    // Where tinyobjloader looks for it; a missing library falls back to the default material.
    const std::string mtl = (objFolder / library).string();
    std::error_code error;
    if (!fs::is_regular_file(mtl, error)) {
      warnings.push_back("mtllib '" + library + "' not found (" + mtl +
                         "): its materials are drawn in the default grey");
      continue;
    }
    checkMtlText(readWholeFile(mtl), mtl);
    libraries.push_back(mtl);
  }
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  const bool parsed = reader.ParseFromFile(path, config);
  if (!parsed || !reader.Error().empty()) {
    std::string message = reader.Error();
    while (!message.empty() && isSpace(message.back())) message.pop_back();
    fileError(path, message.empty() ? "cannot parse file" : message);
  }
  // tinyobjloader only warns about indices past the end of the vertex lists (and
  // silently drops some such faces); a mesh with holes would be worse than an error.
  for (const char* fatal : {"out of bounds", "invalid vertex index"}) {
    const std::string line = firstLineContaining(reader.Warning(), fatal);
    if (!line.empty()) fileError(path, line);
  }

  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  const size_t positionCount = attrib.vertices.size() / 3;
  const size_t normalCount = attrib.normals.size() / 3;
  const size_t texcoordCount = attrib.texcoords.size() / 2;

  ObjData result;
  result.files = std::move(libraries);
  result.warnings = std::move(warnings);
  for (const tinyobj::material_t& source : reader.GetMaterials()) {
    const ObjMaterialDesc desc{source.name,
                               toVec3(source.diffuse),
                               toVec3(source.specular),
                               toVec3(source.emission),
                               source.shininess,
                               source.ior,
                               source.dissolve,
                               source.illum};
    result.materials.push_back(materialFromMtl(desc));
    result.diffuseMaps.push_back(resolveTexturePath(objFolder, source.diffuse_texname));
  }
  const uint32_t fileMaterialCount = uint32_t(result.materials.size());
  uint32_t defaultMaterial = std::numeric_limits<uint32_t>::max();

  // Normals and uvs are kept if any corner has them; corners without get the
  // face-derived normal (below) and uv (0,0).
  bool anyNormal = false, anyTexcoord = false;
  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    for (const tinyobj::index_t& index : shape.mesh.indices) {
      anyNormal = anyNormal || index.normal_index >= 0;
      anyTexcoord = anyTexcoord || index.texcoord_index >= 0;
    }
  }

  Mesh& mesh = result.mesh;
  mesh.name = fs::path(path).stem().string();
  std::unordered_map<CornerKey, uint32_t, CornerKeyHash> cornerVertex;
  size_t faceNumber = 0;
  std::vector<uint32_t> polygon;

  static constexpr const char* kVertex = "vertex";
  const auto vertexFor = [&](const tinyobj::index_t& index) {
    const auto check = [&](int value, size_t count, const char* what) {
      // Negative only where a relative index reached before the first entry;
      // -1 means "none" for normals and texcoords.
      if (value >= int64_t(count) || value < (what == kVertex ? 0 : -1)) {
        fileError(path, "face " + std::to_string(faceNumber) + ": " + what + " index " +
                            std::to_string(value) + " out of range (" + std::to_string(count) +
                            ")");
      }
    };
    check(index.vertex_index, positionCount, kVertex);
    check(index.normal_index, normalCount, "normal");
    check(index.texcoord_index, texcoordCount, "texcoord");

    const CornerKey key{index.vertex_index, index.texcoord_index, index.normal_index};
    const auto [slot, inserted] = cornerVertex.try_emplace(key, mesh.vertexCount);
    if (!inserted) return slot->second;
    if (mesh.vertexCount == std::numeric_limits<uint32_t>::max())
      fileError(path, "too many vertices");
    mesh.positions.push_back(toVec3(&attrib.vertices[3 * size_t(index.vertex_index)]));
    const int n = index.normal_index, t = index.texcoord_index;
    if (anyNormal)
      mesh.normals.push_back(n >= 0 ? toVec3(&attrib.normals[3 * size_t(n)]) : vec3(0));
    if (anyTexcoord) {
      mesh.uvs.push_back(
          t >= 0 ? vec2(attrib.texcoords[2 * size_t(t)], attrib.texcoords[2 * size_t(t) + 1])
                 : vec2(0));
    }
    return mesh.vertexCount++;
  };

  for (const tinyobj::shape_t& shape : reader.GetShapes()) {
    size_t offset = 0;
    for (size_t face = 0; face < shape.mesh.num_face_vertices.size(); ++face, ++faceNumber) {
      const size_t corners = shape.mesh.num_face_vertices[face];
      polygon.clear();
      for (size_t k = 0; k < corners; ++k)
        polygon.push_back(vertexFor(shape.mesh.indices[offset + k]));
      offset += corners;

      int material = face < shape.mesh.material_ids.size() ? shape.mesh.material_ids[face] : -1;
      if (material < 0 || uint32_t(material) >= fileMaterialCount) {
        if (defaultMaterial == std::numeric_limits<uint32_t>::max()) {
          defaultMaterial = uint32_t(result.materials.size());
          Material fallback;
          fallback.name = "default";
          fallback.albedo = vec3(0.8f);
          result.materials.push_back(fallback);
          result.diffuseMaps.emplace_back();
        }
        material = int(defaultMaterial);
      }
      // Triangulation already happened in tinyobjloader; the fan is a safety net
      // that keeps the file's winding (the front of an emissive face) either way.
      for (size_t corner = 2; corner < polygon.size(); ++corner) {
        mesh.indices.insert(mesh.indices.end(), {polygon[0], polygon[corner - 1], polygon[corner]});
        mesh.materialIds.push_back(uint32_t(material));
      }
    }
  }
  if (mesh.indices.empty()) fileError(path, "no faces");
  repairNormals(mesh);
  return result;
}

}  // namespace penumbra
