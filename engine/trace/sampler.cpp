#include "trace/sampler.h"

namespace penumbra {

namespace {
// Dimension slots of the camera point; integrator dimensions start after them.
constexpr uint32_t kImageDim = 0, kLensDim = 1, kTimeDim = 2, kFirstIntegratorDim = 3;
}  // namespace

uint32_t roundUpPowerOfTwo(uint32_t v) {
  uint32_t p = 1;
  while (p < v && p < (1u << 31)) p <<= 1;
  return p;
}

void PixelSampler::startSample(int px, int py, uint32_t sampleIndex, uint32_t stream) {
  if (!havePixel_ || px != px_ || py != py_ || stream != stream_) {
    px_ = px;
    py_ = py;
    stream_ = stream;
    havePixel_ = true;
    const uint64_t pixel = (uint64_t(uint32_t(py)) << 32) | uint32_t(px);
    // Stream 0 keeps the key it always had, so the pixel's own samples do not change.
    pixelKey_ = stream == 0 ? hashValues(seed_, pixel) : hashValues(seed_, pixel, stream);
    cachedCount_ = 0;
  }
  sampleIndex_ = sampleIndex;
  if (kind_ == SamplerKind::LowDiscrepancy) {
    // What every dimension's shuffle of this sample shares (shuffledIndex).
    blockKey_ = mixBits32(sampleIndex & ~(setSize_ - 1));
    reversedLocal_ = reverseBits(sampleIndex & (setSize_ - 1));
  }
  dimension_ = kFirstIntegratorDim;
  peekedDimension_ = kNoPeek;
  // Each sample gets a state hashed from the pixel and its index: PCG streams that share a
  // state and differ only in their increment (the sample index) are correlated, and a pixel's
  // mean then strays far more than its variance says.
  if (kind_ == SamplerKind::Independent)
    rng_.seedWith(hashValues(pixelKey_, uint64_t(sampleIndex)), pixelKey_);
}

PixelSampler::DimensionKeys PixelSampler::keysFor(uint32_t dimension) const {
  const uint64_t h = hashValues(pixelKey_, dimension);
  const uint32_t shuffle = uint32_t(h);
  return {shuffle, uint32_t(h >> 32), uint32_t(mixBits(h)),
          order_ == BlockOrder::Shuffled ? permuteKeys(shuffle) : PermuteKeys{}};
}

const PixelSampler::DimensionKeys& PixelSampler::keys(uint32_t dimension) {
  if (dimension >= kCachedDimensions) return overflow_ = keysFor(dimension);
  while (cachedCount_ <= dimension) {
    cache_[cachedCount_] = keysFor(cachedCount_);
    ++cachedCount_;
  }
  return cache_[dimension];
}

uint32_t PixelSampler::shuffledIndex(const DimensionKeys& k) const {
  const uint32_t block = sampleIndex_ & ~(setSize_ - 1);
  const uint32_t key = block ? mixBits32(k.shuffle ^ blockKey_) : k.shuffle;
  if (order_ == BlockOrder::Nested)
    return block | nestedPermuteReversedIndex(reversedLocal_, setSize_, key);
  const uint32_t local = sampleIndex_ & (setSize_ - 1);
  return block |
         (block ? permuteIndex(local, setSize_, key) : permuteIndex(local, setSize_, k.firstBlock));
}

CameraSample PixelSampler::cameraSample(bool needLens, bool needTime) {
  CameraSample s;
  if (kind_ == SamplerKind::Independent) {
    s.imageX = px_ + rng_.nextFloat();
    s.imageY = py_ + rng_.nextFloat();
    s.lensU = rng_.nextFloat();
    s.lensV = rng_.nextFloat();
    s.time = rng_.nextFloat();
    return s;
  }
  // Each aligned block of setSize samples is a (0,m,2)-net in the image offsets (and in
  // the lens), whatever the shuffled order inside the block.
  const DimensionKeys& image = keys(kImageDim);
  const uint32_t imageIndex = shuffledIndex(image);
  s.imageX = px_ + vanDerCorput(imageIndex, image.scrambleX);
  s.imageY = py_ + sobol2(imageIndex, image.scrambleY);
  if (needLens) {
    const DimensionKeys& lens = keys(kLensDim);
    const uint32_t lensIndex = shuffledIndex(lens);
    s.lensU = vanDerCorput(lensIndex, lens.scrambleX);
    s.lensV = sobol2(lensIndex, lens.scrambleY);
  }
  if (needTime) {
    const DimensionKeys& time = keys(kTimeDim);
    s.time = vanDerCorput(shuffledIndex(time), time.scrambleX);
  }
  return s;
}

float PixelSampler::next1D(Scrambling scrambling) {
  if (kind_ == SamplerKind::Independent) return rng_.nextFloat();
  const DimensionKeys& k = keys(dimension_++);
  const uint32_t index = shuffledIndex(k);
  return scrambling == Scrambling::Owen ? owenVanDerCorput(index, k.scrambleX)
                                        : vanDerCorput(index, k.scrambleX);
}

glm::vec2 PixelSampler::next2D(Scrambling scrambling) {
  if (kind_ == SamplerKind::Independent) {
    const float a = rng_.nextFloat();
    return {a, rng_.nextFloat()};
  }
  if (dimension_ == peekedDimension_ && scrambling == peekedScrambling_) {
    ++dimension_;
    return peeked_;
  }
  return lowDiscrepancy2D(dimension_++, scrambling);
}

bool PixelSampler::peek2D(uint32_t ahead, glm::vec2& value, Scrambling scrambling) {
  if (kind_ == SamplerKind::Independent) return false;
  peekedDimension_ = dimension_ + ahead;
  peekedScrambling_ = scrambling;
  value = peeked_ = lowDiscrepancy2D(peekedDimension_, scrambling);
  return true;
}

glm::vec2 PixelSampler::lowDiscrepancy2D(uint32_t dimension, Scrambling scrambling) {
  const DimensionKeys& k = keys(dimension);
  const uint32_t index = shuffledIndex(k);
  if (scrambling == Scrambling::Owen)
    return {owenVanDerCorput(index, k.scrambleX),
            toUnitFloat(owenScramble(sobol2Bits(index, 0), k.scrambleY))};
  return {vanDerCorput(index, k.scrambleX), sobol2(index, k.scrambleY)};
}

}  // namespace penumbra
