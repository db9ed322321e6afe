#include "methods/bp/mdnet.h"

#include "core/rng.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <glm/common.hpp>
#include <glm/exponential.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace penumbra::mdnet {

namespace {

int parameterCount(const Config& c) {
  return c.inputs * c.hidden + c.hidden + c.hidden * kOutputs + kOutputs;
}

void check(const Config& c) {
  if (c.inputs < 1 || c.inputs > kMaxInputs || c.hidden < 1 || c.hidden > kMaxHidden)
    throw std::invalid_argument("mdnet: inputs must be 1.." + std::to_string(kMaxInputs) +
                                " and hidden 1.." + std::to_string(kMaxHidden));
}

float sigmoid(float x) { return 1.0f / (1.0f + std::exp(-std::clamp(x, -30.0f, 30.0f))); }

// A standard normal number from two uniform ones (Box-Muller).
float normal(Pcg32& rng) {
  const float u1 = std::max(rng.nextFloat(), 1e-7f), u2 = rng.nextFloat();
  return std::sqrt(-2.0f * std::log(u1)) * std::cos(6.28318531f * u2);
}

// Visits every used weight with its index in the flat order of Net::m and Net::v.
template <typename Net_, typename Visit>
void forEachWeight(Net_& net, const Config& c, Visit visit) {
  int k = 0;
  for (int i = 0; i < c.inputs; ++i)
    for (int j = 0; j < c.hidden; ++j) visit(net.w1[i][j], k++);
  for (int j = 0; j < c.hidden; ++j) visit(net.b1[j], k++);
  for (int j = 0; j < c.hidden; ++j)
    for (int o = 0; o < kOutputs; ++o) visit(net.w2[j][o], k++);
  for (int o = 0; o < kOutputs; ++o) visit(net.b2[o], k++);
}

// The hidden layer and the standardised outputs for one input vector.
void forward(const Net& net, const Config& c, const float* x, float* h, float* out) {
  for (int j = 0; j < c.hidden; ++j) {
    float z = net.b1[j];
    for (int i = 0; i < c.inputs; ++i) z += x[i] * net.w1[i][j];
    h[j] = sigmoid(z);
  }
  for (int o = 0; o < kOutputs; ++o) {
    float y = net.b2[o];
    for (int j = 0; j < c.hidden; ++j) y += h[j] * net.w2[j][o];
    out[o] = y;
  }
}

// The targets' mean and spread per channel, which the outputs are scaled by.
void standardise(Net& net, std::span<const glm::vec3> targets) {
  if (targets.empty()) return;
  glm::dvec3 sum(0.0), sumSq(0.0);
  for (const glm::vec3& t : targets) {
    sum += glm::dvec3(t);
    sumSq += glm::dvec3(t) * glm::dvec3(t);
  }
  const double n = double(targets.size());
  const glm::dvec3 mean = sum / n;
  const glm::dvec3 variance = glm::max(sumSq / n - mean * mean, glm::dvec3(0.0));
  net.targetMean = glm::vec3(mean);
  net.targetScale = glm::vec3(glm::sqrt(variance)) + 1e-6f;
}

}  // namespace

void init(Net& net, const Config& config, uint64_t seed) {
  check(config);
  Pcg32 rng(seed, 0x6d646e6574ULL);
  for (auto& row : net.w1)
    for (float& w : row) w = 0.0f;
  for (auto& row : net.w2)
    for (float& w : row) w = 0.0f;
  for (int i = 0; i < config.inputs; ++i)
    for (int j = 0; j < config.hidden; ++j) net.w1[i][j] = normal(rng);
  for (int j = 0; j < kMaxHidden; ++j) net.b1[j] = j < config.hidden ? 0.5f * normal(rng) : 0.0f;
  for (int j = 0; j < config.hidden; ++j)
    for (int o = 0; o < kOutputs; ++o) net.w2[j][o] = 0.3f * normal(rng);
  for (float& b : net.b2) b = 0.0f;
  net.targetMean = glm::vec3(0.0f);
  net.targetScale = glm::vec3(1.0f);
  net.m.assign(size_t(parameterCount(config)), 0.0f);
  net.v.assign(size_t(parameterCount(config)), 0.0f);
  net.step = 0;
}

float fit(Net& net, const Config& config, std::span<const float> inputs,
          std::span<const glm::vec3> targets) {
  check(config);
  const size_t n = targets.size();
  if (inputs.size() != n * size_t(config.inputs))
    throw std::invalid_argument("mdnet::fit: " + std::to_string(inputs.size()) + " inputs for " +
                                std::to_string(n) + " samples");
  if (net.m.size() != size_t(parameterCount(config))) init(net, config, 0);
  if (n == 0) return 0.0f;
  standardise(net, targets);
  std::vector<glm::vec3> standard(n);
  for (size_t k = 0; k < n; ++k) standard[k] = (targets[k] - net.targetMean) / net.targetScale;

  const int H = config.hidden, I = config.inputs;
  const float gradScale = 2.0f / (float(n) * float(kOutputs));
  Net grad;  // only its weights are used
  float loss = 0.0f;
  for (int epoch = 0; epoch < config.epochs; ++epoch) {
    forEachWeight(grad, config, [](float& g, int) { g = 0.0f; });
    double squared = 0;
    for (size_t k = 0; k < n; ++k) {
      const float* x = &inputs[k * size_t(I)];
      float h[kMaxHidden], out[kOutputs], g[kOutputs];
      forward(net, config, x, h, out);
      for (int o = 0; o < kOutputs; ++o) {
        const float e = out[o] - standard[k][o];
        squared += double(e) * double(e);
        g[o] = gradScale * e;
        grad.b2[o] += g[o];
      }
      for (int j = 0; j < H; ++j) {
        float back = 0.0f;
        for (int o = 0; o < kOutputs; ++o) {
          grad.w2[j][o] += h[j] * g[o];
          back += g[o] * net.w2[j][o];
        }
        const float gh = back * h[j] * (1.0f - h[j]);
        grad.b1[j] += gh;
        for (int i = 0; i < I; ++i) grad.w1[i][j] += x[i] * gh;
      }
    }
    loss = float(squared / (double(n) * kOutputs));
    // Adam (Kingma and Ba 2015) with its usual constants.
    ++net.step;
    const float c1 = 1.0f / (1.0f - std::pow(0.9f, float(net.step)));
    const float c2 = 1.0f / (1.0f - std::pow(0.999f, float(net.step)));
    std::vector<float>& m = net.m;
    std::vector<float>& v = net.v;
    std::vector<float> flat(m.size());
    forEachWeight(grad, config, [&](float& g, int k) { flat[size_t(k)] = g; });
    forEachWeight(net, config, [&](float& w, int k) {
      const float g = flat[size_t(k)];
      m[size_t(k)] = 0.9f * m[size_t(k)] + 0.1f * g;
      v[size_t(k)] = 0.999f * v[size_t(k)] + 0.001f * g * g;
      w -= config.learningRate * (m[size_t(k)] * c1) / (std::sqrt(v[size_t(k)] * c2) + 1e-8f);
    });
  }
  return loss;
}

glm::vec3 predict(const Net& net, const Config& config, const float* x) {
  float h[kMaxHidden], out[kOutputs];
  forward(net, config, x, h, out);
  return glm::vec3(out[0], out[1], out[2]) * net.targetScale + net.targetMean;
}

glm::vec3 average(const Net& net, const Config& config, std::span<const float> points) {
  const size_t count = points.size() / size_t(config.inputs);
  if (count == 0) return net.targetMean;
  glm::dvec3 sum(0.0);
  for (size_t k = 0; k < count; ++k)
    sum += glm::dvec3(predict(net, config, &points[k * size_t(config.inputs)]));
  return glm::vec3(sum / double(count));
}

namespace {
bool hasAvx2() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }
bool hasAvx512() {
  return hasAvx2() && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
         __builtin_cpu_supports("avx512dq");
}
}  // namespace

int batchLanes() {
  static const int lanes = hasAvx512() ? 16 : hasAvx2() ? 8 : 4;
  return lanes;
}

std::vector<float> fitBatch(const Config& config, std::span<Net* const> nets, const Batch& batch,
                            int lanes) {
  check(config);
  const int pixels = batch.pixelCount();
  if (int(nets.size()) != pixels || batch.offsets.back() != batch.targets.size() ||
      batch.inputs.size() != batch.targets.size() * size_t(config.inputs))
    throw std::invalid_argument("mdnet::fitBatch: the batch's sizes do not match");
  if (lanes != 0 && lanes != 4 && !(lanes == 8 && hasAvx2()) && !(lanes == 16 && hasAvx512()))
    throw std::invalid_argument("mdnet::fitBatch: " + std::to_string(lanes) +
                                " lanes are not available on this CPU");
  const int L = lanes != 0 ? lanes : batchLanes(), I = config.inputs, H = config.hidden;
  const size_t P = size_t(parameterCount(config));
  std::vector<float> loss(size_t(pixels), 0.0f);
  const int groups = (pixels + L - 1) / L;
  tbb::parallel_for(tbb::blocked_range<int>(0, groups, 1), [&](const tbb::blocked_range<int>& r) {
    const size_t lanes = static_cast<size_t>(L);
    std::vector<float> x, y, valid, gradScale(lanes), params(P * lanes), m(P * lanes), v(P * lanes),
        scratch(P * lanes), groupLoss(lanes);
    std::vector<int> step(lanes);
    for (int group = r.begin(); group != r.end(); ++group) {
      const int first = group * L;
      uint32_t samples = 0;
      for (int lane = 0; lane < L && first + lane < pixels; ++lane)
        samples = std::max(
            samples, batch.offsets[size_t(first + lane) + 1] - batch.offsets[size_t(first + lane)]);
      x.assign(size_t(samples) * size_t(I) * size_t(L), 0.0f);
      y.assign(size_t(samples) * 3 * size_t(L), 0.0f);
      valid.assign(size_t(samples) * size_t(L), 0.0f);
      std::fill(params.begin(), params.end(), 0.0f);
      std::fill(m.begin(), m.end(), 0.0f);
      std::fill(v.begin(), v.end(), 0.0f);
      std::fill(gradScale.begin(), gradScale.end(), 0.0f);
      std::fill(step.begin(), step.end(), 0);
      for (int lane = 0; lane < L && first + lane < pixels; ++lane) {
        Net& net = *nets[size_t(first + lane)];
        if (net.m.size() != P) init(net, config, 0);
        const uint32_t begin = batch.offsets[size_t(first + lane)];
        const uint32_t n = batch.offsets[size_t(first + lane) + 1] - begin;
        const std::span<const glm::vec3> targets(batch.targets.data() + begin, n);
        standardise(net, targets);
        for (uint32_t k = 0; k < n; ++k) {
          const float* in = &batch.inputs[(size_t(begin) + k) * size_t(I)];
          for (int i = 0; i < I; ++i)
            x[(size_t(k) * size_t(I) + size_t(i)) * size_t(L) + size_t(lane)] = in[i];
          const glm::vec3 t = (targets[k] - net.targetMean) / net.targetScale;
          for (int o = 0; o < 3; ++o)
            y[(size_t(k) * 3 + size_t(o)) * size_t(L) + size_t(lane)] = t[o];
          valid[size_t(k) * size_t(L) + size_t(lane)] = 1.0f;
        }
        gradScale[size_t(lane)] = n ? 2.0f / (float(n) * float(kOutputs)) : 0.0f;
        forEachWeight(net, config, [&](float& w, int k) {
          params[size_t(k) * size_t(L) + size_t(lane)] = w;
          m[size_t(k) * size_t(L) + size_t(lane)] = net.m[size_t(k)];
          v[size_t(k) * size_t(L) + size_t(lane)] = net.v[size_t(k)];
        });
        step[size_t(lane)] = net.step;
      }
      detail::Group g;
      g.inputs = I;
      g.hidden = H;
      g.samples = int(samples);
      g.epochs = config.epochs;
      g.learningRate = config.learningRate;
      g.x = x.data();
      g.y = y.data();
      g.valid = valid.data();
      g.gradScale = gradScale.data();
      g.params = params.data();
      g.m = m.data();
      g.v = v.data();
      g.step = step.data();
      g.loss = groupLoss.data();
      g.scratch = scratch.data();
      if (L == 16)
        detail::trainGroupAvx512(g);
      else if (L == 8)
        detail::trainGroupAvx2(g);
      else
        detail::trainGroupSse(g);
      for (int lane = 0; lane < L && first + lane < pixels; ++lane) {
        Net& net = *nets[size_t(first + lane)];
        const uint32_t n =
            batch.offsets[size_t(first + lane) + 1] - batch.offsets[size_t(first + lane)];
        if (n == 0) continue;  // left as it was
        forEachWeight(net, config, [&](float& w, int k) {
          w = params[size_t(k) * size_t(L) + size_t(lane)];
          net.m[size_t(k)] = m[size_t(k) * size_t(L) + size_t(lane)];
          net.v[size_t(k)] = v[size_t(k) * size_t(L) + size_t(lane)];
        });
        net.step = step[size_t(lane)];
        loss[size_t(first + lane)] = groupLoss[size_t(lane)] / (float(n) * float(kOutputs));
      }
    }
  });
  return loss;
}

std::vector<float> haltonPoints(int dimensions, int count, std::span<const float> lo,
                                std::span<const float> hi) {
  static constexpr int kBases[] = {2, 3, 5, 7, 11, 13, 17, 19};
  if (dimensions < 1 || dimensions > int(std::size(kBases)) || lo.size() < size_t(dimensions) ||
      hi.size() < size_t(dimensions) || count < 0)
    throw std::invalid_argument("mdnet::haltonPoints: bad dimensions or bounds");
  std::vector<float> points(size_t(count) * size_t(dimensions));
  for (int k = 0; k < count; ++k)
    for (int d = 0; d < dimensions; ++d) {
      // The radical inverse of k + 1 in the dimension's base.
      const int base = kBases[d];
      double value = 0, scale = 1.0 / base;
      for (int i = k + 1; i > 0; i /= base, scale /= base) value += (i % base) * scale;
      points[size_t(k) * size_t(dimensions) + size_t(d)] =
          lo[size_t(d)] + float(value) * (hi[size_t(d)] - lo[size_t(d)]);
    }
  return points;
}

}  // namespace penumbra::mdnet
