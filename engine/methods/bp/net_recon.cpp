#include "methods/bp/net_recon.h"

#include <glm/gtc/packing.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>

namespace penumbra::bp {

namespace {

// Demodulation: (radiance - emission) / (albedo + kAlbedoEpsilon), as the filter's.
constexpr float kAlbedoEpsilon = 0.01f;
// A pixel trains only when its samples' relative spread is at least this: below it the
// neighbourhood is flat and every window already does well.
constexpr float kMinRelativeSpread = 0.02f;
// A network needs this many neighbourhood samples for a first training.
constexpr uint32_t kMinSamples = 24;
// A network corrects at most one sample per this many it was fitted on (NetRecon::correction).
constexpr uint32_t kSamplesPerCorrection = 8;
// Footprint points each neighbourhood sample is paired with for a network's mean.
constexpr size_t kNodesPerSample = 1;
// Due networks are fitted in parts of this many pixels, the cancel flag read between them.
constexpr size_t kFitPart = 1024;

// The film's per-sample variance of a pixel's filtered part over its mean squared.
float relativeSpread(const FilmPixel& px) {
  if (px.count < 2) return 0.0f;
  const float variance = luminance(px.residualM2) / float(px.count - 1);
  const float mean = luminance(px.residual);
  return variance / (mean * mean + 1e-4f);
}

}  // namespace

NetRecon::NetRecon(int width, int height, bool lens, bool time, const NetReconConfig& config)
    : width_(width),
      height_(height),
      lens_(lens),
      time_(time),
      settings_(config),
      kept_(size_t(width) * size_t(height)),
      storing_(size_t(width) * size_t(height), 1),
      slotOf_(size_t(width) * size_t(height), -1) {
  config_.inputs = 2 + (lens ? 2 : 0) + (time ? 1 : 0) + 2;
  config_.hidden = config.hidden;
  config_.epochs = config.epochs;
  // The pixel's footprint: offsets from its centre in [-0.5, 0.5]^2. The other dimensions are
  // taken from the neighbourhood's samples (their distribution, which need not be uniform).
  const float lo[2] = {-0.5f, -0.5f}, hi[2] = {0.5f, 0.5f};
  nodes_ = mdnet::haltonPoints(2, config.nodes, lo, hi);
}

void NetRecon::inputsOf(int px, int py, const CameraSample& cs, const PathFeatures& f,
                        float* in) const {
  int k = 0;
  in[k++] = cs.imageX - float(px) - 0.5f;
  in[k++] = cs.imageY - float(py) - 0.5f;
  if (lens_) in[k++] = cs.lensU - 0.5f, in[k++] = cs.lensV - 0.5f;
  if (time_) in[k++] = cs.time - 0.5f;
  in[k++] = f.lightChart.x - 0.5f;
  in[k++] = f.lightChart.y - 0.5f;
}

void NetRecon::record(size_t p, int px, int py, const CameraSample& cs, vec3 radiance,
                      const PathFeatures& f) {
  if (!storing_[p] || kept_[p].size() >= size_t(settings_.capacity)) return;
  const vec3 target = (radiance - f.emission) / (f.albedo + kAlbedoEpsilon);
  if (!std::isfinite(target.x + target.y + target.z)) return;
  float in[mdnet::kMaxInputs] = {};
  inputsOf(px, py, cs, f, in);
  NetSample s;
  for (int i = 0; i < mdnet::kMaxInputs; ++i) s.in[i] = glm::packHalf1x16(in[i]);
  for (int c = 0; c < 3; ++c) s.target[c] = target[c];
  kept_[p].push_back(s);
}

vec3 NetRecon::correction(size_t p, int px, int py, const CameraSample& cs, const PathFeatures& f) {
  const int32_t slot = slotOf_[p];
  if (slot < 0 || !slots_[size_t(slot)].corrects) return vec3(0.0f);
  Slot& s = slots_[size_t(slot)];
  if (s.corrected >= s.trainedAt / kSamplesPerCorrection) return vec3(0.0f);
  ++s.corrected;
  float in[mdnet::kMaxInputs] = {};
  inputsOf(px, py, cs, f, in);
  // The same rounding as the stored samples the network was fitted on.
  for (int i = 0; i < config_.inputs; ++i) in[i] = glm::unpackHalf1x16(glm::packHalf1x16(in[i]));
  const vec3 c = (f.albedo + kAlbedoEpsilon) * (mdnet::predict(s.net, config_, in) - s.mean);
  return std::isfinite(c.x + c.y + c.z) ? c : vec3(0.0f);
}

void NetRecon::choose(const Film& film) {
  const size_t n = kept_.size();
  std::vector<float> spread(n);
  std::vector<uint32_t> order;
  for (size_t p = 0; p < n; ++p) {
    // A network that corrects its pixel keeps it: the corrected samples vary less.
    const bool corrects = slotOf_[p] >= 0 && slots_[size_t(slotOf_[p])].corrects;
    spread[p] = corrects ? INFINITY : relativeSpread(film[p]);
    if (spread[p] >= kMinRelativeSpread) order.push_back(uint32_t(p));
  }
  const size_t limit = std::min(order.size(), size_t(double(settings_.share) * double(n)));
  // The widest spreads first; ties by pixel index, so that the choice is deterministic.
  std::partial_sort(order.begin(), order.begin() + std::ptrdiff_t(limit), order.end(),
                    [&](uint32_t a, uint32_t b) {
                      return spread[a] != spread[b] ? spread[a] > spread[b] : a < b;
                    });
  order.resize(limit);
  std::vector<uint8_t> chosen(n, 0);
  for (uint32_t p : order) chosen[p] = 1;
  for (size_t p = 0; p < n; ++p)
    if (!chosen[p] && slotOf_[p] >= 0) {
      freeSlots_.push_back(uint32_t(slotOf_[p]));
      slotOf_[p] = -1;
    }
  for (uint32_t p : order) {
    if (slotOf_[p] >= 0) continue;
    uint32_t slot;
    if (!freeSlots_.empty()) {
      slot = freeSlots_.back();
      freeSlots_.pop_back();
    } else {
      slot = uint32_t(slots_.size());
      slots_.emplace_back();
    }
    Slot& s = slots_[slot];
    mdnet::init(s.net, config_, p);
    s.pixel = p;
    s.trainedAt = 0;
    s.mean = vec3(0.0f);
    s.heldOut = 0;
    s.corrects = false;
    s.corrected = 0;
    slotOf_[p] = int32_t(slot);
  }
  // Only the chosen pixels' neighbourhoods keep samples from now on.
  std::fill(storing_.begin(), storing_.end(), uint8_t(0));
  const int r = settings_.reach;
  for (uint32_t p : order) {
    const int x = int(p % uint32_t(width_)), y = int(p / uint32_t(width_));
    for (int qy = std::max(0, y - r); qy <= std::min(height_ - 1, y + r); ++qy)
      for (int qx = std::max(0, x - r); qx <= std::min(width_ - 1, x + r); ++qx)
        storing_[size_t(qy) * size_t(width_) + size_t(qx)] = 1;
  }
  for (size_t p = 0; p < n; ++p)
    if (!storing_[p] && kept_[p].capacity()) std::vector<NetSample>().swap(kept_[p]);
}

uint32_t NetRecon::neighbourhoodCount(size_t p) const {
  const int x = int(p % size_t(width_)), y = int(p / size_t(width_)), r = settings_.reach;
  uint32_t count = 0;
  for (int qy = std::max(0, y - r); qy <= std::min(height_ - 1, y + r); ++qy)
    for (int qx = std::max(0, x - r); qx <= std::min(width_ - 1, x + r); ++qx)
      if (qx != x || qy != y)
        count += uint32_t(kept_[size_t(qy) * size_t(width_) + size_t(qx)].size());
  return count;
}

void NetRecon::gather(const std::vector<uint32_t>& due, mdnet::Batch& batch) const {
  const int inputs = config_.inputs, r = settings_.reach;
  for (uint32_t slot : due) {
    const size_t p = slots_[slot].pixel;
    const int x = int(p % size_t(width_)), y = int(p / size_t(width_));
    for (int qy = std::max(0, y - r); qy <= std::min(height_ - 1, y + r); ++qy)
      for (int qx = std::max(0, x - r); qx <= std::min(width_ - 1, x + r); ++qx) {
        if (qx == x && qy == y) continue;  // never the pixel's own samples
        for (const NetSample& s : kept_[size_t(qy) * size_t(width_) + size_t(qx)]) {
          for (int i = 0; i < inputs; ++i) batch.inputs.push_back(glm::unpackHalf1x16(s.in[i]));
          batch.inputs[batch.inputs.size() - size_t(inputs)] += float(qx - x);
          batch.inputs[batch.inputs.size() - size_t(inputs) + 1] += float(qy - y);
          batch.targets.emplace_back(s.target[0], s.target[1], s.target[2]);
        }
      }
    batch.offsets.push_back(uint32_t(batch.targets.size()));
  }
}

bool NetRecon::train(const Film& film, uint64_t rays, const std::atomic<bool>* cancel) {
  choose(film);
  // Due: never trained and enough samples, or grown by `growth` since the last training.
  std::vector<uint32_t> first, again;
  for (uint32_t slot = 0; slot < slots_.size(); ++slot) {
    const Slot& s = slots_[slot];
    if (slotOf_[s.pixel] != int32_t(slot)) continue;  // free
    const uint32_t count = neighbourhoodCount(s.pixel);
    if (s.trainedAt == 0 && count >= kMinSamples)
      first.push_back(slot);
    else if (s.trainedAt > 0 && float(count) >= settings_.growth * float(s.trainedAt))
      again.push_back(slot);
  }
  // The widest spreads first, ties by pixel.
  std::vector<float> spread(slots_.size());
  for (uint32_t slot : first) spread[slot] = relativeSpread(film[slots_[slot].pixel]);
  std::sort(first.begin(), first.end(), [&](uint32_t a, uint32_t b) {
    return spread[a] != spread[b] ? spread[a] > spread[b] : slots_[a].pixel < slots_[b].pixel;
  });
  const double allowed = kTrainingPerRay * double(rays);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<uint32_t> due;
    mdnet::Config config = config_;
    if (pass == 1) config.epochs = std::max(1, config_.epochs / 2);
    // Within the budget: the pixels in order until the next one's cost would pass it.
    for (uint32_t slot : pass == 0 ? first : again) {
      const uint64_t cost =
          uint64_t(neighbourhoodCount(slots_[slot].pixel)) * uint64_t(config.epochs);
      if (double(trained_ + cost) > allowed) break;
      trained_ += cost;
      due.push_back(slot);
    }
    for (size_t begin = 0; begin < due.size(); begin += kFitPart) {
      if (cancel && cancel->load()) return false;
      const std::vector<uint32_t> part(
          due.begin() + std::ptrdiff_t(begin),
          due.begin() + std::ptrdiff_t(std::min(due.size(), begin + kFitPart)));
      mdnet::Batch batch;
      gather(part, batch);
      std::vector<mdnet::Net*> nets;
      for (uint32_t slot : part) nets.push_back(&slots_[slot].net);
      mdnet::fitBatch(config, nets, batch);
      fits_ += part.size();
      for (size_t j = 0; j < part.size(); ++j) {
        Slot& s = slots_[part[j]];
        s.trainedAt = batch.offsets[j + 1] - batch.offsets[j];
        // The mean over the pixel: each of the neighbourhood's samples' other dimensions (their
        // distribution: the light's sampling density, not a uniform one) paired with
        // kNodesPerSample points of the footprint in turn.
        const size_t count = s.trainedAt, inputs = size_t(config_.inputs);
        const float* x = &batch.inputs[size_t(batch.offsets[j]) * inputs];
        glm::dvec3 sum(0.0);
        const size_t nodes = nodes_.size() / 2;
        for (size_t i = 0; i < count * kNodesPerSample; ++i) {
          float point[mdnet::kMaxInputs];
          const size_t k = i % nodes, sample = i / kNodesPerSample;
          std::copy(x + sample * inputs, x + (sample + 1) * inputs, point);
          point[0] = nodes_[2 * k];
          point[1] = nodes_[2 * k + 1];
          sum += glm::dvec3(mdnet::predict(s.net, config_, point));
        }
        s.mean = vec3(sum / double(count * kNodesPerSample));
        // The held-out error: the pixel's own samples, which the fit never saw.
        const std::vector<NetSample>& own = kept_[s.pixel];
        double err = 0, m = 0, m2 = 0;
        for (const NetSample& o : own) {
          float point[mdnet::kMaxInputs];
          for (size_t i = 0; i < inputs; ++i) point[i] = glm::unpackHalf1x16(o.in[i]);
          const vec3 y(o.target[0], o.target[1], o.target[2]);
          const vec3 d = mdnet::predict(s.net, config_, point) - y;
          err += double(glm::dot(d, d));
          m += double(y.x + y.y + y.z);
          m2 += double(glm::dot(y, y));
        }
        const double n = double(own.size());
        const double variance = n > 1 ? (m2 - m * m / (3.0 * n)) / n : 0.0;
        s.heldOut = n > 1 ? float(err / n / std::max(variance, 1e-12)) : 0.0f;
        // It corrects the pixel's next samples only if it predicts its earlier ones.
        s.corrects = n > 1 && s.heldOut <= settings_.maxHeldOut;
      }
    }
  }
  return true;
}

std::vector<float> NetRecon::trainedMap() const {
  std::vector<float> map(kept_.size(), 0.0f);
  for (size_t p = 0; p < map.size(); ++p)
    if (slotOf_[p] >= 0 && slots_[size_t(slotOf_[p])].corrects) map[p] = 1.0f;
  return map;
}

std::vector<std::string> NetRecon::roleLabels() {
  return {"keeps samples", "not fitted yet", "held out (too wrong)", "corrects",
          "capped (corrected its share)"};
}

std::vector<float> NetRecon::roleMap() const {
  std::vector<float> map(kept_.size(), float(kRoleNone));
  for (size_t p = 0; p < map.size(); ++p) {
    const int32_t slot = slotOf_[p];
    if (slot < 0) {
      if (storing_[p] && !kept_[p].empty()) map[p] = float(kStores);
      continue;
    }
    const Slot& s = slots_[size_t(slot)];
    const Role role = s.trainedAt == 0                                     ? kWaiting
                      : !s.corrects                                        ? kHeldOut
                      : s.corrected >= s.trainedAt / kSamplesPerCorrection ? kCapped
                                                                           : kCorrects;
    map[p] = float(role);
  }
  return map;
}

std::vector<const char*> NetRecon::inputNames() const {
  std::vector<const char*> names = {"x offset", "y offset"};
  if (lens_) names.insert(names.end(), {"lens u", "lens v"});
  if (time_) names.push_back("time");
  names.insert(names.end(), {"light s", "light t"});
  return names;
}

std::optional<InspectedFit> NetRecon::fitAlong(size_t p) const {
  if (slotOf_[p] < 0 || slots_[size_t(slotOf_[p])].trainedAt == 0) return std::nullopt;
  const uint32_t slot = uint32_t(slotOf_[p]);
  const Slot& s = slots_[slot];
  mdnet::Batch batch;
  gather({slot}, batch);
  const size_t inputs = size_t(config_.inputs), count = batch.targets.size();
  if (count == 0) return std::nullopt;
  // The partial dependence is averaged over at most this many of the samples, evenly spread.
  constexpr size_t kBackground = 96;
  constexpr int kPoints = 17;
  const size_t step = std::max<size_t>(1, count / kBackground);
  InspectedFit best;
  size_t bestInput = 0;
  float bestSpread = -1.0f;
  for (size_t i = 0; i < inputs; ++i) {
    float lo = INFINITY, hi = -INFINITY;
    for (size_t j = 0; j < count; ++j) {
      lo = std::min(lo, batch.inputs[j * inputs + i]);
      hi = std::max(hi, batch.inputs[j * inputs + i]);
    }
    std::vector<float> curve(kPoints);
    for (int t = 0; t < kPoints; ++t) {
      const float v = lo + (hi - lo) * float(t) / float(kPoints - 1);
      double sum = 0;
      size_t used = 0;
      for (size_t j = 0; j < count; j += step, ++used) {
        float point[mdnet::kMaxInputs];
        std::copy_n(&batch.inputs[j * inputs], inputs, point);
        point[i] = v;
        sum += double(luminance(mdnet::predict(s.net, config_, point)));
      }
      curve[size_t(t)] = float(sum / double(used));
    }
    const auto [mn, mx] = std::minmax_element(curve.begin(), curve.end());
    if (*mx - *mn > bestSpread) {
      bestSpread = *mx - *mn;
      bestInput = i;
      best.lo = lo;
      best.hi = hi;
      best.curve = std::move(curve);
    }
  }
  best.input = inputNames()[bestInput];
  for (size_t j = 0; j < count; ++j)
    best.samples.emplace_back(batch.inputs[j * inputs + bestInput], luminance(batch.targets[j]));
  for (const NetSample& o : kept_[p])
    best.own.emplace_back(glm::unpackHalf1x16(o.in[bestInput]),
                          luminance(vec3(o.target[0], o.target[1], o.target[2])));
  return best;
}

NetRecon::PixelNetwork NetRecon::pixelNetwork(size_t p) const {
  PixelNetwork info;
  info.kept = uint32_t(kept_[p].size());
  if (slotOf_[p] < 0) return info;
  const Slot& s = slots_[size_t(slotOf_[p])];
  info.trained = s.trainedAt > 0;
  info.corrects = s.corrects;
  info.heldOut = s.heldOut;
  info.samples = s.trainedAt;
  info.mean = s.mean;
  return info;
}

size_t NetRecon::correctingPixels() const {
  size_t count = 0;
  for (int32_t slot : slotOf_) count += slot >= 0 && slots_[size_t(slot)].corrects;
  return count;
}

std::vector<float> NetRecon::heldOutMap() const {
  std::vector<float> map(kept_.size(), 0.0f);
  for (size_t p = 0; p < map.size(); ++p)
    if (slotOf_[p] >= 0 && slots_[size_t(slotOf_[p])].trainedAt > 0)
      map[p] = slots_[size_t(slotOf_[p])].heldOut;
  return map;
}

size_t NetRecon::memoryBytes() const {
  size_t bytes = kept_.capacity() * sizeof(std::vector<NetSample>) + storing_.capacity() +
                 slotOf_.capacity() * sizeof(int32_t) + nodes_.capacity() * sizeof(float) +
                 freeSlots_.capacity() * sizeof(uint32_t);
  for (const auto& k : kept_) bytes += k.capacity() * sizeof(NetSample);
  for (const Slot& s : slots_)
    bytes += sizeof(Slot) + (s.net.m.capacity() + s.net.v.capacity()) * sizeof(float);
  return bytes;
}

}  // namespace penumbra::bp
