#include "scene/environment.h"

#include "core/constants.h"
#include "core/image_io.h"
#include "scene/scene.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace penumbra {

namespace {

// Index of the last entry of cdf[0..n] that is <= u, in [0, n - 1].
int findInterval(const float* cdf, int n, float u) {
  const float* it = std::upper_bound(cdf, cdf + n + 1, u);
  return std::clamp(int(it - cdf) - 1, 0, n - 1);
}
// Walker's alias table over weights[0..n) summing to `sum` (> 0), built by Vose's method:
// each entry keeps its own column with probability `keep` and sends the rest of its 1/n share
// to `alias`, so that column i is drawn with probability weights[i] / sum. Deterministic.
void buildAliasTable(const std::vector<double>& weights, double sum, std::vector<uint32_t>& small,
                     std::vector<uint32_t>& large, EnvironmentLight::AliasEntry* out) {
  const size_t n = weights.size();
  std::vector<double> scaled(n);
  small.clear();
  large.clear();
  for (size_t i = n; i-- > 0;) {
    scaled[i] = weights[i] / sum * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    const uint32_t s = small.back(), l = large.back();
    small.pop_back();
    large.pop_back();
    out[s].keep = float(scaled[s]);
    out[s].alias = l;
    scaled[l] -= 1.0 - scaled[s];
    (scaled[l] < 1.0 ? small : large).push_back(l);
  }
  // What is left is 1 up to rounding: it keeps itself.
  for (uint32_t i : small) out[i].keep = 1.0f, out[i].alias = i;
  for (uint32_t i : large) out[i].keep = 1.0f, out[i].alias = i;
}
}  // namespace

float equirectU(vec3 d) {
  const float u = 0.5f + std::atan2(d.z, d.x) / (2.0f * kPi);
  return std::clamp(u >= 1.0f ? u - 1.0f : u, 0.0f, 1.0f);
}

glm::vec2 directionToEquirect(vec3 d) {
  return {equirectU(d), std::acos(std::clamp(d.y, -1.0f, 1.0f)) / kPi};
}

vec3 equirectToDirection(glm::vec2 ut) {
  const float theta = kPi * ut.y, phi = 2.0f * kPi * (ut.x - 0.5f);
  const float s = std::sin(theta);
  return {s * std::cos(phi), std::cos(theta), s * std::sin(phi)};
}

std::shared_ptr<const Image> readEnvironmentMap(const std::string& path, std::string* warning) {
  Image image;
  try {
    image = readImage(path);
  } catch (const ImageIoError& e) {
    throw SceneError(e.what());
  }
  if (image.empty()) throw SceneError(path + ": the environment map is empty");
  // Real maps carry a few texels below zero (the ringing of lossy compression, DWA's among
  // them, next to black) and now and then one that is not finite: each such value reads as 0,
  // and one warning says how many there were and where the first was.
  size_t negative = 0, nonFinite = 0;
  float lowest = 0.0f;
  int firstX = -1, firstY = -1;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      vec3& c = image.pixels[size_t(y) * size_t(image.width) + size_t(x)];
      bool repaired = false;
      for (int k = 0; k < 3; ++k) {
        if (!std::isfinite(c[k])) {
          ++nonFinite;
        } else if (c[k] < 0.0f) {
          ++negative;
          lowest = std::min(lowest, c[k]);
        } else {
          continue;
        }
        c[k] = 0.0f;
        repaired = true;
      }
      if (repaired && firstX < 0) firstX = x, firstY = y;
    }
  if (firstX >= 0 && warning) {
    std::ostringstream text;
    text << path << ": " << negative << " negative and " << nonFinite
         << " non-finite texel values read as 0 (the first at pixel (" << firstX << ", " << firstY
         << ")";
    if (negative > 0) text << "; the lowest " << lowest;
    text << ")";
    *warning = text.str();
  }
  return std::make_shared<const Image>(std::move(image));
}

std::shared_ptr<const Image> builtinEnvironmentMap() {
  // 128 x 64 texels: fine enough for the broad lobes below, small enough to build at once.
  constexpr int kWidth = 128, kHeight = 64;
  Image image(kWidth, kHeight);
  const vec3 key = glm::normalize(vec3(-0.55f, 0.65f, 0.55f));  // high, front left
  const vec3 fill = glm::normalize(vec3(0.8f, 0.25f, 0.35f));   // low, right
  const vec3 rim = glm::normalize(vec3(0.1f, 0.45f, -0.9f));    // behind
  for (int y = 0; y < kHeight; ++y)
    for (int x = 0; x < kWidth; ++x) {
      const vec3 d = equirectToDirection({(float(x) + 0.5f) / kWidth, (float(y) + 0.5f) / kHeight});
      // A grey room: brighter overhead, a darker floor, a soft step at the horizon.
      const float up = std::clamp(d.y * 4.0f, -1.0f, 1.0f);
      float level = d.y >= 0 ? 0.55f + 0.35f * d.y : 0.25f;
      level = 0.5f * (1 + up) * level + 0.5f * (1 - up) * 0.25f;
      // Soft boxes: broad lobes around three directions.
      auto lobe = [&](vec3 axis, float width, float gain) {
        const float c = glm::dot(d, axis);
        return gain * std::exp((c - 1.0f) / width);
      };
      level += lobe(key, 0.04f, 6.0f) + lobe(fill, 0.08f, 1.2f) + lobe(rim, 0.05f, 2.0f);
      image.at(x, y) = vec3(level);
    }
  return std::make_shared<const Image>(std::move(image));
}

EnvironmentLight::EnvironmentLight(std::shared_ptr<const Image> map, float strength,
                                   float rotationDegrees)
    : map_(std::move(map)), strength_(strength) {
  const float r = rotationDegrees * kPi / 180.0f;
  cosRotation_ = std::cos(r);
  sinRotation_ = std::sin(r);
  width_ = map_->width;
  height_ = map_->height;
  cosRowEdge_.resize(size_t(height_) + 1);
  for (int j = 0; j <= height_; ++j) cosRowEdge_[size_t(j)] = float(std::cos(kPiD * j / height_));
  cosRowEdge_.front() = 1.0f;
  cosRowEdge_.back() = -1.0f;

  // Cell weights: the mean over the texel of the bilinear lookup's luminance, times its solid
  // angle; rows' sums make the marginal. A bilinear lookup spreads a texel a quarter of a texel
  // into its neighbours, so a texel's mean is 3/4 of itself plus 1/8 of each neighbour, per
  // axis (wrapping in azimuth, clamped at the poles): a bright texel's neighbours get the
  // samples their share of its light needs, with no fireflies from BSDF samples there.
  const size_t w = size_t(width_), h = size_t(height_);
  std::vector<float> texelLuminance(w * h), rowFiltered(w * h);
  for (size_t j = 0; j < h; ++j)
    for (size_t i = 0; i < w; ++i) texelLuminance[j * w + i] = luminance(map_->at(int(i), int(j)));
  for (size_t j = 0; j < h; ++j)
    for (size_t i = 0; i < w; ++i) {
      const float* row = &texelLuminance[j * w];
      rowFiltered[j * w + i] = 0.75f * row[i] + 0.125f * (row[(i + w - 1) % w] + row[(i + 1) % w]);
    }
  std::vector<float> cellLuminance(w * h);
  for (size_t j = 0; j < h; ++j)
    for (size_t i = 0; i < w; ++i) {
      const size_t up = j > 0 ? j - 1 : 0, down = j + 1 < h ? j + 1 : h - 1;
      cellLuminance[j * w + i] = 0.75f * rowFiltered[j * w + i] +
                                 0.125f * (rowFiltered[up * w + i] + rowFiltered[down * w + i]);
    }
  cells_.assign(h * w, AliasEntry{});
  std::vector<double> rowSum(h, 0.0);
  std::vector<double> cell(w);
  std::vector<uint32_t> small, large;
  for (size_t j = 0; j < h; ++j) {
    const double solidAngle =
        2.0 * kPiD / double(w) * (double(cosRowEdge_[j]) - double(cosRowEdge_[j + 1]));
    double running = 0;
    for (size_t i = 0; i < w; ++i) {
      cell[i] = double(cellLuminance[j * w + i]) * solidAngle;
      running += cell[i];
    }
    rowSum[j] = running;
    if (running > 0) buildAliasTable(cell, running, small, large, &cells_[j * w]);
  }
  double total = 0;
  for (double s : rowSum) total += s;
  integral_ = total * double(strength_);
  rowCdf_.assign(h + 1, 0.0f);
  double acc = 0;
  for (size_t j = 0; j < h; ++j) {
    acc += rowSum[j];
    rowCdf_[j + 1] = total > 0 ? float(acc / total) : float(j + 1) / float(h);
  }
  rowCdf_[h] = 1.0f;
  // A guide table, so that a draw's row is found by a short forward scan rather than a binary
  // search (whose branches mispredict): entry k is the row of (k - 1) / height, at or before
  // the row of any u with int(u * height) = k (such a u exceeds (k - 1) / height by far more
  // than rounding).
  rowGuide_.resize(h + 1);
  rowGuide_[0] = 0;
  for (size_t k = 1; k <= h; ++k)
    rowGuide_[k] = findInterval(rowCdf_.data(), height_, float(double(k - 1) / double(h)));
  if (!(total > 0)) return;
  // A texel's probability over its solid angle: its luminance over the total.
  pdfs_.resize(h * w);
  for (size_t c = 0; c < h * w; ++c) pdfs_[c] = float(double(cellLuminance[c]) / total);
  for (size_t j = 0; j < h; ++j)
    for (size_t i = 0; i < w; ++i) {
      AliasEntry& e = cells_[j * w + i];
      e.aliasPdf = pdfs_[j * w + e.alias];
    }
}

EnvironmentLight EnvironmentLight::constant(vec3 radiance) {
  return EnvironmentLight(std::make_shared<const Image>(1, 1, radiance), 1.0f, 0.0f);
}

vec3 EnvironmentLight::toMap(vec3 d) const {
  // Inverse of toWorld: rotate by -rotation about +y.
  return {cosRotation_ * d.x - sinRotation_ * d.z, d.y, sinRotation_ * d.x + cosRotation_ * d.z};
}

vec3 EnvironmentLight::toWorld(vec3 d) const {
  // Right-hand rule about +y: +x turns towards -z.
  return {cosRotation_ * d.x + sinRotation_ * d.z, d.y, -sinRotation_ * d.x + cosRotation_ * d.z};
}

vec3 EnvironmentLight::lookup(float u, float t) const {
  const Image& m = *map_;
  // Bilinear between texel centres: wraps in azimuth, clamps at the poles.
  const float x = u * float(width_) - 0.5f, y = t * float(height_) - 0.5f;
  const float fx = std::floor(x), fy = std::floor(y);
  const float tx = x - fx, ty = y - fy;
  // Wrapped into [0, width): the modulo's divisions only for columns past one turn (u in
  // [0, 1] gives fx in [-1, width - 1]).
  const int ix = int(fx);
  const int x0 = ix >= 0 && ix < width_    ? ix
                 : ix < 0 && ix >= -width_ ? ix + width_
                                           : ((ix % width_) + width_) % width_;
  const int x1 = x0 + 1 < width_ ? x0 + 1 : 0;
  const int y0 = std::clamp(int(fy), 0, height_ - 1), y1 = std::clamp(int(fy) + 1, 0, height_ - 1);
  const vec3 c = (1 - ty) * ((1 - tx) * m.at(x0, y0) + tx * m.at(x1, y0)) +
                 ty * ((1 - tx) * m.at(x0, y1) + tx * m.at(x1, y1));
  return c * strength_;
}

vec3 EnvironmentLight::radiance(vec3 direction, float* pdf) const {
  if (constant()) {
    if (pdf) *pdf = pdfs_.empty() ? 0.0f : pdfs_[0];
    return map_->pixels[0] * strength_;
  }
  const glm::vec2 ut = directionToEquirect(toMap(direction));
  if (pdf) *pdf = cellPdf(ut);
  return lookup(ut.x, ut.y);
}

float EnvironmentLight::cellPdf(glm::vec2 ut) const {
  if (black()) return 0.0f;
  return pdfs_[cellAt(ut)];
}

size_t EnvironmentLight::cellAt(glm::vec2 ut) const {
  // The texel under the coordinates; rows are equal steps of theta, so t finds the row.
  const int j = std::clamp(int(ut.y * float(height_)), 0, height_ - 1);
  const int i = std::clamp(int(ut.x * float(width_)), 0, width_ - 1);
  return size_t(j) * size_t(width_) + size_t(i);
}

int EnvironmentLight::rowOf(float u) const {
  // findInterval's answer, the last row whose cdf is at most u, found forward from the guide
  // (the cdf is non-decreasing).
  if (!(u > 0.0f)) return findInterval(rowCdf_.data(), height_, u);
  int j = rowGuide_[size_t(std::min(int(u * float(height_)), height_))];
  while (j + 1 < height_ && rowCdf_[size_t(j) + 1] <= u) ++j;
  return j;
}

bool EnvironmentLight::sample(glm::vec2 u, vec3& direction, float& pdf, vec3* radiance) const {
  if (black()) return false;
  const int j = rowOf(u.y);
  const float r0 = rowCdf_[size_t(j)], r1 = rowCdf_[size_t(j) + 1];
  const float vRemapped = r1 > r0 ? std::clamp((u.y - r0) / (r1 - r0), 0.0f, 1.0f) : 0.5f;
  // The column from the row's alias table; the draw's leftover fraction places the direction
  // within the texel.
  const float x = std::clamp(u.x, 0.0f, 1.0f) * float(width_);
  const int slot = std::min(int(x), width_ - 1);
  const float f = std::clamp(x - float(slot), 0.0f, 1.0f);
  const size_t cell = size_t(j) * size_t(width_) + size_t(slot);
  const AliasEntry& e = cells_[cell];
  int i = slot;
  float uRemapped;
  if (f < e.keep) {
    uRemapped = f / e.keep;
    pdf = pdfs_[cell];
  } else {
    i = int(e.alias);
    uRemapped = std::min((f - e.keep) / (1.0f - e.keep), 1.0f);
    pdf = e.aliasPdf;
  }
  if (!(pdf > 0)) return false;
  // Uniform in azimuth and in cos theta within the texel.
  const float cosTheta =
      cosRowEdge_[size_t(j)] + vRemapped * (cosRowEdge_[size_t(j) + 1] - cosRowEdge_[size_t(j)]);
  const float sinTheta = std::sqrt(std::max(0.0f, 1.0f - cosTheta * cosTheta));
  const float uMap = (float(i) + uRemapped) / float(width_);
  const float phi = 2.0f * kPi * (uMap - 0.5f);
  direction = toWorld({sinTheta * std::cos(phi), cosTheta, sinTheta * std::sin(phi)});
  if (radiance)
    *radiance = constant() ? map_->pixels[0] * strength_
                           : lookup(uMap, std::acos(std::clamp(cosTheta, -1.0f, 1.0f)) / kPi);
  return true;
}

void EnvironmentLight::prefetch(glm::vec2 u) const {
  if (black() || constant()) return;
  const int j = rowOf(u.y);
  const int slot = std::min(int(std::clamp(u.x, 0.0f, 1.0f) * float(width_)), width_ - 1);
  __builtin_prefetch(&cells_[size_t(j) * size_t(width_) + size_t(slot)]);
  __builtin_prefetch(&pdfs_[size_t(j) * size_t(width_) + size_t(slot)]);
  // The bilinear lookup reads the texel's row and one beside it.
  const int up = std::max(j - 1, 0), down = std::min(j + 1, height_ - 1);
  __builtin_prefetch(&map_->at(slot, j));
  __builtin_prefetch(&map_->at(slot, up));
  __builtin_prefetch(&map_->at(slot, down));
}

void EnvironmentLight::prefetchDirection(vec3 direction) const {
  if (black() || constant()) return;
  const glm::vec2 ut = directionToEquirect(toMap(direction));
  const size_t cell = cellAt(ut);
  __builtin_prefetch(&pdfs_[cell]);
  const int j = int(cell / size_t(width_)), i = int(cell % size_t(width_));
  // The bilinear lookup reads this row and the one nearer the coordinates' side of it.
  const int other =
      std::clamp(ut.y * float(height_) - float(j) < 0.5f ? j - 1 : j + 1, 0, height_ - 1);
  __builtin_prefetch(&map_->at(i, j));
  __builtin_prefetch(&map_->at(i, other));
}

float EnvironmentLight::pdf(vec3 direction) const {
  if (constant()) return pdfs_.empty() ? 0.0f : pdfs_[0];
  return cellPdf(directionToEquirect(toMap(direction)));
}

}  // namespace penumbra
