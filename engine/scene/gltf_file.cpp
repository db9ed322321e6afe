#include "scene/gltf_file.h"

#include "scene/gltf_accessors.h"

#include <nlohmann/json.hpp>

#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace penumbra::gltf {

namespace fs = std::filesystem;

uint32_t littleEndian32(const std::string& bytes, size_t at) {
  return uint32_t(uint8_t(bytes[at])) | uint32_t(uint8_t(bytes[at + 1])) << 8 |
         uint32_t(uint8_t(bytes[at + 2])) << 16 | uint32_t(uint8_t(bytes[at + 3])) << 24;
}

namespace {

// Refuses a URI that names a network location (any scheme but data:) or an absolute path.
void checkUri(const std::string& path, const std::string& where, const std::string& uri) {
  if (uri.rfind("data:", 0) == 0) return;
  const size_t colon = uri.find(':');
  const size_t slash = uri.find('/');
  const bool scheme = colon != std::string::npos && colon > 0 &&
                      (slash == std::string::npos || colon < slash) &&
                      std::isalpha(static_cast<unsigned char>(uri[0]));
  const bool windowsDrive = scheme && colon == 1;
  if (scheme && !windowsDrive)
    fail(path, where,
         "URI '" + uri + "' names a network location; only relative paths and data: URIs are read");
  if (windowsDrive || uri.rfind('/', 0) == 0 || uri.rfind('\\', 0) == 0 || uri.rfind("//", 0) == 0)
    fail(path, where, "URI '" + uri + "' is an absolute path; only relative paths are read");
}

// A URI's %XX escapes decoded, as tinygltf reads the file ("my%20tex.png" is "my tex.png",
// which Blender's exporter writes for a texture named with spaces); other text as it is.
std::string percentDecoded(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += char(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

}  // namespace

std::string readFileBytes(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) fail(path, "", "cannot open file");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  bytes << in.rdbuf();
  if (!in && !in.eof()) fail(path, "", "read error");
  return std::move(bytes).str();
}

// The JSON part of a .gltf, or of a .glb (its first chunk).
std::string jsonText(const std::string& path, const std::string& bytes, bool binary) {
  if (!binary) return bytes;
  if (bytes.size() < 20 || bytes.compare(0, 4, "glTF") != 0)
    fail(path, "", "not a binary glTF file (no 'glTF' header)");
  const uint32_t version = littleEndian32(bytes, 4), length = littleEndian32(bytes, 12);
  if (version != 2) fail(path, "", "glTF version " + std::to_string(version) + " (expected 2)");
  if (littleEndian32(bytes, 16) != 0x4E4F534Au)  // "JSON"
    fail(path, "", "the first chunk of a .glb must be JSON");
  if (length > bytes.size() - 20)
    fail(path, "",
         "JSON chunk of " + std::to_string(length) + " bytes runs past the end of the file");
  return bytes.substr(20, length);
}

// Checks every buffer's and image's URI; returns the files the relative ones name, and each
// image's URI (empty for one in a buffer view) in `imageUris`.
bool relabelDataUris(std::string& json) {
  bool changed = false;
  for (const char* type : {"image/webp", "image/ktx2", "image/avif"}) {
    const std::string from = std::string("\"data:") + type + ";base64,";
    const std::string to = "\"data:application/octet-stream;base64,";
    for (size_t at = json.find(from); at != std::string::npos; at = json.find(from, at)) {
      json.replace(at, from.size(), to);
      at += to.size();
      changed = true;
    }
  }
  return changed;
}

std::vector<std::string> checkUris(const std::string& path, const std::string& json,
                                   std::vector<std::string>& imageUris) {
  std::vector<std::string> files;
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(json);
  } catch (const nlohmann::json::exception& e) {
    fail(path, "", std::string("invalid JSON: ") + e.what());
  }
  if (!root.is_object()) fail(path, "", "the top level is not a JSON object");
  for (const char* array : {"buffers", "images"}) {
    if (!root.contains(array) || !root[array].is_array()) continue;
    const auto& items = root[array];
    const bool images = std::string(array) == "images";
    if (images) imageUris.assign(items.size(), "");
    for (size_t i = 0; i < items.size(); ++i)
      if (items[i].is_object() && items[i].contains("uri") && items[i]["uri"].is_string()) {
        const std::string uri = items[i]["uri"].get<std::string>();
        if (images && uri.rfind("data:", 0) != 0) imageUris[i] = uri;
        checkUri(path, indexed(array, i) + ".uri", uri);
        if (uri.rfind("data:", 0) != 0)
          files.push_back(
              (fs::path(path).parent_path() / percentDecoded(uri)).lexically_normal().string());
      }
  }
  return files;
}

}  // namespace penumbra::gltf
