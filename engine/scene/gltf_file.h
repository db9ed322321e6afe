// A glTF file's container for gltf_io.cpp: its bytes, the JSON of a .gltf or of a .glb's first
// chunk, and the URIs of its buffers and images (data: or a relative path, nothing else).
// Errors name the file and the element. Internal to the
// glTF reader.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace penumbra::gltf {

// The little-endian 32-bit number at byte `at` (at + 4 <= bytes.size()).
uint32_t littleEndian32(const std::string& bytes, size_t at);

// The whole file; throws SceneError naming it when it cannot be read.
std::string readFileBytes(const std::string& path);

// The JSON part of a .gltf (`binary` false: the bytes themselves), or of a .glb (its first
// chunk, after its header is checked).
std::string jsonText(const std::string& path, const std::string& bytes, bool binary);

// tinygltf decodes data: URIs of a few MIME types only and takes the others for file names:
// relabels those of image/webp, image/ktx2 and image/avif as application/octet-stream (an
// image's contents decide its format). Returns whether it changed `json`.
bool relabelDataUris(std::string& json);

// Checks every buffer's and image's URI; returns the files the relative URIs name, and each image's
// URI (empty for one in a buffer view) in `imageUris`.
std::vector<std::string> checkUris(const std::string& path, const std::string& json,
                                   std::vector<std::string>& imageUris);

}  // namespace penumbra::gltf
