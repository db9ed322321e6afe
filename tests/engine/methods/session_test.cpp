// RenderSession: rounds on a worker thread, snapshots after each round, and the controls
// a viewer needs (pause, step, resume, cancel, restart), without the caller ever waiting.
#include "methods/session.h"

#include "methods/bp/paper.h"
#include "scene/scene_loader.h"
#include "tests/test_paths.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace penumbra {
namespace {

std::shared_ptr<PreparedScene> cornell(int size) { return test::shippedScene("cornell", size); }

// The publishing rule: a snapshot as costly as a round of a large image is published after
// every round right after a start, and from four seconds on after more and more tracing, up to
// six times its cost; a cheap one (a small image) a few times a second throughout.
TEST(PublishInterval, LetsCostlySnapshotsTakeAShrinkingShareOfTheTime) {
  EXPECT_DOUBLE_EQ(publishInterval(0.0, 0.01), 0.2);
  EXPECT_DOUBLE_EQ(publishInterval(60.0, 0.01), 0.2);
  EXPECT_DOUBLE_EQ(publishInterval(0.5, 0.8), 0.8);
  EXPECT_DOUBLE_EQ(publishInterval(4.0, 0.8), 0.8);
  EXPECT_DOUBLE_EQ(publishInterval(8.0, 0.8), 1.6);
  EXPECT_DOUBLE_EQ(publishInterval(24.0, 0.8), 4.8);
  EXPECT_DOUBLE_EQ(publishInterval(600.0, 0.8), 4.8);
  // Snapshots' share of a long run: cost / (interval + cost) <= 1/7.
  EXPECT_LE(0.8 / (publishInterval(600.0, 0.8) + 0.8), 1.0 / 7.0 + 1e-12);
}

RenderSession::MethodFactory bpFactory(std::shared_ptr<PreparedScene> scene, int spp,
                                       bool openEnded = false) {
  return [scene, spp, openEnded] {
    RunShape shape = openEnded ? RunShape::progressive(2) : RunShape::batch(spp);
    BpPaperConfig config;
    config.network.epochs = 10;
    return makeBpPaperMethod(*scene, shape, config);
  };
}

// A method that counts how many of its kind are alive: each round takes `roundMs` (cut short by
// a cancel), it never ends, and it holds `bytes` of per-pixel state.
class CountedMethod final : public ProgressiveMethod {
 public:
  struct Counts {
    std::atomic<int> alive{0}, mostAlive{0}, made{0};
    std::mutex mutex;
    std::vector<int> snapshotRounds;  // the round of each snapshot taken, in order
  };
  int snapshotMs = 0;  // what a snapshot costs
  CountedMethod(Counts& counts, int roundMs)
      : ProgressiveMethod(RunShape::progressive(1)), counts_(counts), roundMs_(roundMs) {
    const int alive = ++counts_.alive;
    ++counts_.made;
    int most = counts_.mostAlive.load();
    while (alive > most && !counts_.mostAlive.compare_exchange_weak(most, alive)) {
    }
  }
  ~CountedMethod() override { --counts_.alive; }
  void runRound(const std::atomic<bool>* cancel) override {
    for (int ms = 0; ms < roundMs_ && !(cancel && cancel->load()); ++ms)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    if (!(cancel && cancel->load())) ++rounds_;
  }
  int roundsDone() const override { return rounds_; }
  std::shared_ptr<Snapshot> snapshot(bool, const std::atomic<bool>*) override {
    std::this_thread::sleep_for(std::chrono::milliseconds(snapshotMs));
    {
      const std::lock_guard<std::mutex> lock(counts_.mutex);
      counts_.snapshotRounds.push_back(rounds_);
    }
    auto snap = std::make_shared<Snapshot>();
    snap->round = rounds_;
    snap->width = snap->height = 1;
    snap->raw = snap->reconstructed = Image(1, 1);
    return snap;
  }
  size_t memoryBytes() const override { return state_.size(); }
  PixelInspection inspect(int x, int y) const override {
    return startInspection(x, y, 1, 1, rounds_, "counted");
  }

 protected:
  bool budgetSpent() const override { return false; }

 private:
  Counts& counts_;
  int roundMs_;
  int rounds_ = 0;
  std::vector<uint8_t> state_ = std::vector<uint8_t>(1 << 20);
};

TEST(Session, RunsToTheEndAndPublishesTheFinalSnapshot) {
  RenderSession session(2);
  EXPECT_EQ(session.latest(), nullptr);
  session.start(bpFactory(cornell(16), 8));
  ASSERT_TRUE(session.wait(120));
  EXPECT_EQ(session.state(), RenderSession::State::Finished);
  const auto snap = session.latest();
  ASSERT_NE(snap, nullptr);
  EXPECT_TRUE(snap->final);
  EXPECT_EQ(snap->keptSamples, 8u * 16 * 16);
  // Publishing is throttled (a few a second): the first round and the last at least.
  EXPECT_LE(session.version(), uint64_t(snap->round));
  EXPECT_GE(session.version(), 2u);
}

TEST(Session, StepRunsOneRoundThenPauses) {
  RenderSession session(1);
  session.start(bpFactory(cornell(12), 0, true));
  session.pause();
  ASSERT_TRUE(session.wait(60));
  EXPECT_EQ(session.state(), RenderSession::State::Paused);
  const uint64_t before = session.version();
  const int roundBefore = session.latest() ? session.latest()->round : 0;
  session.step();
  ASSERT_TRUE(session.wait(60));
  EXPECT_EQ(session.state(), RenderSession::State::Paused);
  EXPECT_EQ(session.version(), before + 1);
  EXPECT_EQ(session.latest()->round, roundBefore + 1);
  // Paused means paused: nothing is published meanwhile.
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(session.version(), before + 1);
  session.resume();
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (session.version() < before + 3 && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_GE(session.version(), before + 3);
  session.cancel();
  EXPECT_EQ(session.state(), RenderSession::State::Cancelled);
}

// A restart releases the old view's snapshot at once (a viewer never shows it), so two views'
// snapshots are not alive together while the new method makes its first.
TEST(Session, RestartReleasesTheOldViewsSnapshot) {
  RenderSession session(2);
  auto scene = cornell(16);
  session.start(bpFactory(scene, 0, true));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!session.latest() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const std::weak_ptr<const Snapshot> old = session.latest();
  ASSERT_FALSE(old.expired());
  session.restart(bpFactory(scene, 4), 0);  // pauses before its first round
  EXPECT_EQ(session.latest(), nullptr);
  ASSERT_TRUE(session.wait(60));
  EXPECT_EQ(session.state(), RenderSession::State::Paused);
  EXPECT_EQ(session.latest(), nullptr);
  EXPECT_TRUE(old.expired());
}

TEST(Session, RestartDropsTheOldMethodAndStartsFromTheCoarsePass) {
  RenderSession session(2);
  auto scene = cornell(16);
  session.start(bpFactory(scene, 0, true));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while ((!session.latest() || session.latest()->round < 3) &&
         std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_GE(session.latest()->round, 3);
  session.restart(bpFactory(scene, 4));
  ASSERT_TRUE(session.wait(60));
  EXPECT_EQ(session.state(), RenderSession::State::Finished);
  // 4 spp is all coarse pass: one round.
  EXPECT_EQ(session.latest()->round, 1);
  EXPECT_EQ(session.latest()->keptSamples, 4u * 16 * 16);
}

TEST(Session, CancelReturnsAtOnceAndTheDestructorJoins) {
  auto scene = cornell(64);
  const auto start = std::chrono::steady_clock::now();
  {
    RenderSession session(2);
    session.start(bpFactory(scene, 0, true));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    session.cancel();
    EXPECT_EQ(session.state(), RenderSession::State::Cancelled);
    EXPECT_TRUE(session.wait(0));
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30);
}

TEST(Session, AFailingMethodReportsItsError) {
  RenderSession session(1);
  auto scene = cornell(8);
  session.start([scene] {
    BpPaperConfig config;
    config.slicesPerSide = 9;
    return makeBpPaperMethod(*scene, RunShape{}, config);
  });
  ASSERT_TRUE(session.wait(30));
  EXPECT_EQ(session.state(), RenderSession::State::Failed);
  EXPECT_NE(session.error().find("--slices"), std::string::npos);
}

TEST(Session, InspectsAPixelAfterRoundsAndWhilePaused) {
  RenderSession session(2);
  session.inspect(2, 3);
  session.start(bpFactory(cornell(8), 0, true));
  session.pause();
  ASSERT_TRUE(session.wait(60));
  session.step();
  ASSERT_TRUE(session.wait(60));
  // Taken after the round that ran.
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!session.inspection() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_NE(session.inspection(), nullptr);
  EXPECT_EQ(session.inspection()->x, 2);
  EXPECT_EQ(session.inspection()->y, 3);
  // While paused, a new pixel is inspected without running a round.
  const uint64_t version = session.version();
  const uint64_t inspections = session.inspectionVersion();
  session.inspect(5, 1);
  deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (session.inspectionVersion() == inspections && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_NE(session.inspection(), nullptr);
  EXPECT_EQ(session.inspection()->x, 5);
  EXPECT_TRUE(session.inspection()->valid);
  EXPECT_EQ(session.version(), version);
  EXPECT_EQ(session.state(), RenderSession::State::Paused);
}

// Maps only while wanted (a viewer showing no overlay): the rounds publish none; turned on once
// the session has finished, the last round is published again with its maps, the same images.
TEST(Session, PublishesMapsOnlyWhileTheyAreWanted) {
  RenderSession session(2);
  session.setMapsWanted(false);
  session.start(bpFactory(cornell(12), 4));
  ASSERT_TRUE(session.wait(120));
  ASSERT_EQ(session.state(), RenderSession::State::Finished);
  const auto without = session.latest();
  ASSERT_NE(without, nullptr);
  EXPECT_FALSE(without->withMaps);
  EXPECT_TRUE(without->maps.empty());
  const uint64_t version = session.version();
  session.setMapsWanted(true);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (session.version() == version && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  ASSERT_EQ(session.version(), version + 1);
  const auto with = session.latest();
  EXPECT_TRUE(with->withMaps);
  EXPECT_NE(with->map(maps::ErrorEstimate), nullptr);
  EXPECT_EQ(with->round, without->round);
  EXPECT_EQ(with->keptSamples, without->keptSamples);
  ASSERT_EQ(with->reconstructed.pixels.size(), without->reconstructed.pixels.size());
  for (size_t p = 0; p < with->reconstructed.pixels.size(); ++p)
    ASSERT_EQ(with->reconstructed.pixels[p], without->reconstructed.pixels[p]) << p;
  // Asked again, nothing more is published.
  session.setMapsWanted(true);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(session.version(), version + 1);
}

// A camera drag restarts the session many times a second: each replaced method is freed as soon
// as its round has returned, before the next is made, not once a successor has published.
TEST(Session, ARestartFreesTheReplacedMethodAtOnce) {
  CountedMethod::Counts counts;
  {
    RenderSession session(1);
    // Rounds of 200 ms: no method publishes before it is replaced.
    const auto factory = [&counts] { return std::make_unique<CountedMethod>(counts, 200); };
    constexpr int kRestarts = 30;
    for (int i = 0; i < kRestarts; ++i) {
      session.restart(factory);
      std::this_thread::sleep_for(std::chrono::milliseconds(3));
      EXPECT_LE(counts.alive.load(), 1);
    }
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (!session.latest() && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    ASSERT_NE(session.latest(), nullptr);
    EXPECT_GE(counts.made.load(), 2);  // the worker made several while the restarts came
    EXPECT_EQ(counts.mostAlive.load(), 1);
    EXPECT_EQ(counts.alive.load(), 1);
    // A cancelled method is freed too, without waiting for another start.
    session.cancel();
    while (counts.alive.load() > 0 && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    EXPECT_EQ(counts.alive.load(), 0);
  }
  EXPECT_EQ(counts.alive.load(), 0);
}

// The coarse pass's pictures are published whatever their reconstruction costs: a snapshot
// dearer than its round (as at 1280x720) would otherwise skip the second and third rounds'
// pictures. Later rounds go by publishInterval. Every publication wakes the front end.
TEST(Session, PublishesTheFirstThreeRoundsThenByTheTimeRule) {
  CountedMethod::Counts counts;
  std::atomic<int> woken{0};
  RenderSession session(1);
  session.setOnPublish([&woken] { ++woken; });
  session.start([&counts] {
    auto method = std::make_unique<CountedMethod>(counts, 5);
    method->snapshotMs = 60;
    return method;
  });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (std::chrono::steady_clock::now() < deadline) {
    {
      const std::lock_guard<std::mutex> lock(counts.mutex);
      if (counts.snapshotRounds.size() >= 4) break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  session.cancel();
  const std::lock_guard<std::mutex> lock(counts.mutex);
  ASSERT_GE(counts.snapshotRounds.size(), 4u);
  EXPECT_EQ(counts.snapshotRounds[0], 1);
  EXPECT_EQ(counts.snapshotRounds[1], 2);
  EXPECT_EQ(counts.snapshotRounds[2], 3);
  // Then at least kMinPublishInterval (0.2 s) apart: rounds of 5 ms are skipped between.
  EXPECT_GT(counts.snapshotRounds[3], 4);
  EXPECT_EQ(uint64_t(woken.load()), session.version());
  EXPECT_GE(woken.load(), 3);
}

}  // namespace
}  // namespace penumbra
