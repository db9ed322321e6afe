#include "methods/session.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>
#include <unistd.h>

#include <chrono>
#include <utility>
#include <vector>

namespace penumbra {

namespace {
// Seconds between two published snapshots of a running method, at least.
constexpr double kMinPublishInterval = 0.2;
}  // namespace

namespace {

// Lowers the priority of the calling thread only (Linux: setpriority on a thread id).
void lowerThreadPriority() { setpriority(PRIO_PROCESS, id_t(syscall(SYS_gettid)), 10); }

// Lowers every thread that joins the arena.
class BackgroundObserver final : public tbb::task_scheduler_observer {
 public:
  explicit BackgroundObserver(tbb::task_arena& arena) : tbb::task_scheduler_observer(arena) {
    observe(true);
  }
  ~BackgroundObserver() override { observe(false); }
  void on_scheduler_entry(bool) override { lowerThreadPriority(); }
};

}  // namespace

RenderSession::RenderSession(int threads, bool background)
    : threads_(threads), background_(background) {
  thread_ = std::thread([this] { worker(); });
}

RenderSession::~RenderSession() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
    cancelRound_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

uint64_t RenderSession::start(MethodFactory factory, int rounds) {
  uint64_t generation = 0;
  {
    std::lock_guard lock(mutex_);
    factory_ = std::move(factory);
    ++generation_;
    state_ = State::Running;
    stepsLeft_ = rounds < 0 ? -1 : rounds;
    error_.clear();
    cancelRound_ = true;  // the round of the previous method, if any, stops early
    generation = generation_;
  }
  wake_.notify_all();
  return generation;
}

uint64_t RenderSession::restart(MethodFactory factory, int rounds) {
  return start(std::move(factory), rounds);
}

void RenderSession::pause() {
  std::lock_guard lock(mutex_);
  if (state_ == State::Running) stepsLeft_ = 0;
}

void RenderSession::resume() {
  {
    std::lock_guard lock(mutex_);
    if (state_ != State::Paused && state_ != State::Running) return;
    state_ = State::Running;
    stepsLeft_ = -1;
  }
  wake_.notify_all();
}

void RenderSession::step() {
  {
    std::lock_guard lock(mutex_);
    if (state_ != State::Paused && state_ != State::Running) return;
    state_ = State::Running;
    stepsLeft_ = 1;
  }
  wake_.notify_all();
}

void RenderSession::cancel() {
  {
    std::lock_guard lock(mutex_);
    if (state_ != State::Running && state_ != State::Paused) return;
    ++generation_;
    factory_ = nullptr;
    state_ = State::Cancelled;
    cancelRound_ = true;
  }
  wake_.notify_all();
  idle_.notify_all();
}

RenderSession::State RenderSession::state() const {
  std::lock_guard lock(mutex_);
  return state_;
}

std::string RenderSession::error() const {
  std::lock_guard lock(mutex_);
  return error_;
}

void RenderSession::inspect(int x, int y) {
  {
    std::lock_guard lock(mutex_);
    inspectX_ = x;
    inspectY_ = y;
    inspectPending_ = true;
  }
  wake_.notify_all();
}

std::shared_ptr<const PixelInspection> RenderSession::inspection() const {
  std::lock_guard lock(mutex_);
  return inspection_;
}

std::shared_ptr<const Snapshot> RenderSession::latest(uint64_t* generation) const {
  std::lock_guard lock(mutex_);
  if (generation) *generation = latestGeneration_;
  return latest_;
}

bool RenderSession::wait(double timeoutSeconds) {
  std::unique_lock lock(mutex_);
  const auto until = std::chrono::steady_clock::now() +
                     std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                         std::chrono::duration<double>(std::min(timeoutSeconds, 1e9)));
  return idle_.wait_until(lock, until,
                          [this] { return state_ != State::Running && !publishPending_; });
}

void RenderSession::worker() {
  tbb::task_arena arena(threads_ > 0 ? threads_ : tbb::task_arena::automatic);
  std::unique_ptr<BackgroundObserver> observer;
  if (background_) {
    lowerThreadPriority();
    observer = std::make_unique<BackgroundObserver>(arena);
  }
  // The factory stays alive with its method: it may own what the method refers to (the
  // prepared scene).
  MethodFactory activeFactory;
  std::unique_ptr<ProgressiveMethod> method;
  uint64_t methodGeneration = 0;
  auto drop = [&] {
    method.reset();
    activeFactory = nullptr;
  };
  // A replaced method is freed only after its successor has published its first snapshot:
  // freeing a large method's per-pixel state takes tens of milliseconds, which would
  // otherwise delay the first picture after a restart.
  // (Each keeps the factory that owns what it refers to.)
  std::vector<std::pair<std::unique_ptr<ProgressiveMethod>, MethodFactory>> retired;
  auto retire = [&] {
    if (method) retired.emplace_back(std::move(method), std::move(activeFactory));
    activeFactory = nullptr;
  };
  // Takes the inspection of the asked-for pixel from the idle method (lock held on entry and
  // exit, released while the method works).
  auto takeInspection = [&](std::unique_lock<std::mutex>& held) {
    const int x = inspectX_, y = inspectY_;
    const uint64_t generation = generation_;
    inspectPending_ = false;
    held.unlock();
    method->setInspectedPixel(x, y);
    auto taken = std::make_shared<PixelInspection>(method->inspect(x, y));
    held.lock();
    if (generation == generation_ && x == inspectX_ && y == inspectY_) {
      inspection_ = std::move(taken);
      ++inspectionVersion_;
    }
  };
  // When the last snapshot was published, and what it cost (the publishing rule below).
  bool publishedOnce = false;
  std::chrono::steady_clock::time_point lastPublish{};
  double lastSnapshotCost = 0;
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] {
      return quit_ || state_ == State::Running || (inspectPending_ && method) || publishPending_;
    });
    if (quit_) return;
    if (state_ != State::Running) {
      if (publishPending_ && method && methodGeneration == generation_) {
        const uint64_t generation = generation_;
        cancelRound_ = false;  // a restart meanwhile cuts the reconstruction short
        lock.unlock();
        std::shared_ptr<Snapshot> snapshot;
        try {
          arena.execute([&] { snapshot = method->snapshot(true, &cancelRound_); });
        } catch (const std::exception&) {
          snapshot.reset();  // the next round reports the failure
        }
        lock.lock();
        if (snapshot && generation == generation_ && !cancelRound_) {
          latest_ = std::move(snapshot);
          latestGeneration_ = generation;
          ++version_;
        }
      }
      publishPending_ = false;
      idle_.notify_all();
      // Only an inspection was asked for, between rounds.
      if (methodGeneration == generation_)
        takeInspection(lock);
      else
        inspectPending_ = false;
      continue;
    }
    if (state_ == State::Running && stepsLeft_ == 0) {
      state_ = State::Paused;
      idle_.notify_all();
      continue;
    }
    const uint64_t generation = generation_;
    MethodFactory factory = factory_;
    cancelRound_ = false;
    const int inspectX = inspectX_, inspectY = inspectY_;
    const int stepsLeft = stepsLeft_;
    lock.unlock();

    std::shared_ptr<Snapshot> snapshot;
    std::shared_ptr<PixelInspection> inspection;
    bool finished = false;
    std::string failure;
    try {
      if (!method || methodGeneration != generation) {
        retire();
        activeFactory = std::move(factory);
        method = activeFactory();
        methodGeneration = generation;
        publishedOnce = false;
        lastSnapshotCost = 0;
      }
      method->setInspectedPixel(inspectX, inspectY);
      const bool stepping = stepsLeft > 0;
      arena.execute([&] {
        method->runRound(&cancelRound_);
        if (cancelRound_) return;
        // A reconstruction costs far more than a short round: publish (and reconstruct) the
        // first round, the last, a stepped one, and otherwise at most a few times a second and
        // never more often than the last snapshot's own cost allows (it stays below tracing).
        const double sincePublish =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - lastPublish).count();
        const bool due = !publishedOnce || stepping || method->done() ||
                         sincePublish >= std::max(kMinPublishInterval, lastSnapshotCost);
        if (!due) return;
        const auto snapshotStart = std::chrono::steady_clock::now();
        snapshot = method->snapshot(true, &cancelRound_);
        lastSnapshotCost =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - snapshotStart).count();
        lastPublish = std::chrono::steady_clock::now();
        publishedOnce = true;
        if (cancelRound_) snapshot.reset();  // cut short: it belongs to the old method
      });
      if (snapshot && inspectX >= 0)
        inspection = std::make_shared<PixelInspection>(method->inspect(inspectX, inspectY));
      finished = method->done();
    } catch (const std::exception& e) {
      failure = e.what();
    }

    lock.lock();
    if (generation != generation_) {
      // Restarted or cancelled meanwhile: this round's result belongs to the old method,
      // which goes once the next one has shown something.
      lock.unlock();
      retire();
      lock.lock();
      continue;
    }
    if (!failure.empty()) {
      state_ = State::Failed;
      error_ = failure;
      lock.unlock();
      drop();
      lock.lock();
      idle_.notify_all();
      continue;
    }
    const bool published = snapshot != nullptr;
    // A round whose snapshot the throttle skipped is published once the session pauses, so
    // a paused view shows every sample traced (and a step then adds exactly one round).
    publishPending_ = !published && !finished;
    if (snapshot) {
      latest_ = std::move(snapshot);
      latestGeneration_ = generation;
      ++version_;
    }
    if (inspection && inspectX == inspectX_ && inspectY == inspectY_) {
      inspection_ = std::move(inspection);
      ++inspectionVersion_;
      inspectPending_ = false;
    }
    if (finished) {
      state_ = State::Finished;
      idle_.notify_all();
    } else if (stepsLeft_ > 0) {
      --stepsLeft_;
    }
    if (published && !retired.empty()) {
      lock.unlock();
      retired.clear();
      lock.lock();
    }
  }
}

const char* toString(RenderSession::State state) {
  switch (state) {
    case RenderSession::State::Idle:
      return "idle";
    case RenderSession::State::Running:
      return "running";
    case RenderSession::State::Paused:
      return "paused";
    case RenderSession::State::Finished:
      return "finished";
    case RenderSession::State::Cancelled:
      return "cancelled";
    case RenderSession::State::Failed:
      return "failed";
  }
  return "unknown";
}

}  // namespace penumbra
