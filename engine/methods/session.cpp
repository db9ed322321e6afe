#include "methods/session.h"

#include "core/large_pages.h"

#include <sys/resource.h>
#include <sys/syscall.h>
#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <utility>

namespace penumbra {

namespace {
// Seconds between two published snapshots of a running method, at least.
constexpr double kMinPublishInterval = 0.2;
// A snapshot's reconstruction may cost as much as the tracing between two of them for the
// first kSettleSeconds after a (re)start, when each picture shows much more than the last
// (1, 2, 4, 5, 6 samples per pixel). At 1280x720 BP's first full-resolution picture (5 spp,
// about 2.7 s after a move on two cores) costs 0.6 s and the next ones a quarter of that (they
// redo only what the adaptive round's samples changed): with 2 s here the 6-spp picture, due
// 0.84 s after the 5-spp one, waited for 0.87 s of tracing and came at 4.8 s with 7 spp. From
// then on the tracing between two snapshots grows with the
// time since the start, to kMaxTraceRatio times the last snapshot's cost, so that snapshots
// take at most 1 / (1 + kMaxTraceRatio) of a long run (a 1280x720 reconstruction costs about
// as much as a round of tracing: publishing after every round halved the window's trace speed).
// A small image, whose snapshots cost a few hundredths of a second, still publishes every
// kMinPublishInterval.
constexpr double kSettleSeconds = 4.0;
constexpr double kMaxTraceRatio = 6.0;
// The first rounds of a method publish whatever they cost: the coarse pass of ALGORITHM.md §15
// (1 + 1 + 2 samples per pixel), each of whose pictures halves the noise of the last. By the
// time rule alone a 1280x720 picture's second round (0.23 s of tracing after a 0.24 s
// reconstruction) was skipped, and the window showed the 1-spp picture until the 4-spp one
// landed, about 2.5 s after a move.
constexpr int kAlwaysPublishedRounds = 3;

}  // namespace

double publishInterval(double elapsed, double lastCost) {
  const double ratio = std::clamp(elapsed / kSettleSeconds, 1.0, kMaxTraceRatio);
  return std::max(kMinPublishInterval, lastCost * ratio);
}

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
  // The last snapshot is of the view being replaced: released now (outside the lock) rather
  // than when the new method publishes, so two methods' snapshots are never alive together
  // while the new one's first snapshot is built (at 1920x1080 one is a few hundred MB).
  std::shared_ptr<const Snapshot> replaced;
  {
    std::lock_guard lock(mutex_);
    replaced = std::move(latest_);
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

void RenderSession::setMapsWanted(bool wanted) {
  std::lock_guard lock(mutex_);
  if (wanted == mapsWanted_) return;
  mapsWanted_ = wanted;
  // No round runs to bring them: the last round's snapshot is made again, with its maps.
  if (wanted && state_ != State::Running && latest_ && !latest_->withMaps &&
      latestGeneration_ == generation_) {
    publishPending_ = true;
    wake_.notify_all();
  }
}

void RenderSession::publishLocked(std::shared_ptr<const Snapshot> snapshot, uint64_t generation) {
  latest_ = std::move(snapshot);
  latestGeneration_ = generation;
  ++version_;
  if (onPublish_) onPublish_();
}

void RenderSession::setOnPublish(std::function<void()> onPublish) {
  std::lock_guard lock(mutex_);
  onPublish_ = std::move(onPublish);
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

// What the worker thread keeps between rounds: the running method with the factory that owns
// what it refers to (the prepared scene), and when the last snapshot was published and what it
// cost (the publishing rule in runRound).
struct RenderSession::Worker {
  explicit Worker(int threads) : arena(threads > 0 ? threads : tbb::task_arena::automatic) {}
  tbb::task_arena arena;
  MethodFactory activeFactory;
  std::unique_ptr<ProgressiveMethod> method;
  uint64_t methodGeneration = 0;
  int rounds = 0;  // of the method, this one included
  std::chrono::steady_clock::time_point methodStart{}, lastPublish{};
  double lastSnapshotCost = 0;

  // Frees the method (then the factory that owns what it refers to). Only the worker thread
  // touches the method, and only between rounds, when none of its tasks runs: a replaced
  // method goes at once, before its successor is made, so rapid restarts (a camera drag)
  // never hold two methods' per-pixel state; its large blocks are kept for the successor's
  // film and planes, which then need no fresh pages (core/large_pages.h).
  void drop() {
    if (!method && !activeFactory) return;
    method.reset();
    activeFactory = nullptr;
    trimMallocHeaps();
  }
};

void RenderSession::takeInspection(Worker& w, std::unique_lock<std::mutex>& held) {
  const int x = inspectX_, y = inspectY_;
  const uint64_t generation = generation_;
  inspectPending_ = false;
  held.unlock();
  w.method->setInspectedPixel(x, y);
  auto taken = std::make_shared<PixelInspection>(w.method->inspect(x, y));
  held.lock();
  if (generation == generation_ && x == inspectX_ && y == inspectY_) {
    inspection_ = std::move(taken);
    ++inspectionVersion_;
  }
}

void RenderSession::releaseWhileIdle(std::unique_lock<std::mutex>& lock) {
  // The reconstruction's planes kept for its next round (core/large_pages.h) wait for a round
  // that is not coming: give them back while the session has no work.
  lock.unlock();
  returnFreedMemory();
  lock.lock();
}

void RenderSession::serveIdle(Worker& w, std::unique_lock<std::mutex>& lock) {
  if (w.method && w.methodGeneration != generation_) {
    // Cancelled (or replaced) while no round ran: nothing of it is published any more.
    lock.unlock();
    w.drop();
    lock.lock();
  }
  if (publishPending_ && w.method && w.methodGeneration == generation_) {
    const uint64_t generation = generation_;
    const bool maps = mapsWanted_;
    cancelRound_ = false;  // a restart meanwhile cuts the reconstruction short
    lock.unlock();
    w.method->setMapsWanted(maps);
    std::shared_ptr<Snapshot> snapshot;
    try {
      w.arena.execute([&] { snapshot = w.method->snapshot(true, &cancelRound_); });
    } catch (const std::exception&) {
      snapshot.reset();  // the next round reports the failure
    }
    lock.lock();
    if (snapshot && generation == generation_ && !cancelRound_) {
      publishLocked(std::move(snapshot), generation);
    }
  }
  publishPending_ = false;
  idle_.notify_all();
  // Only an inspection was asked for, between rounds.
  if (w.methodGeneration == generation_ && w.method)
    takeInspection(w, lock);
  else
    inspectPending_ = false;
}

RenderSession::RoundResult RenderSession::runRound(Worker& w, const RoundRequest& request) {
  RoundResult r;
  try {
    if (!w.method || w.methodGeneration != request.generation) {
      w.drop();
      w.activeFactory = request.factory;
      w.method = w.activeFactory();
      w.methodGeneration = request.generation;
      w.rounds = 0;
      w.lastSnapshotCost = 0;
      w.methodStart = std::chrono::steady_clock::now();
    }
    ProgressiveMethod& method = *w.method;
    method.setInspectedPixel(request.inspectX, request.inspectY);
    method.setMapsWanted(request.mapsWanted);
    const bool stepping = request.stepsLeft > 0;
    w.arena.execute([&] {
      method.runRound(&cancelRound_);
      if (cancelRound_) return;
      // A reconstruction costs far more than a short round: publish (and reconstruct) the
      // first rounds, the last, a stepped one, and otherwise at most a few times a second and
      // never more often than the last snapshot's own cost allows (publishInterval).
      const auto now = std::chrono::steady_clock::now();
      const double sincePublish = std::chrono::duration<double>(now - w.lastPublish).count();
      const double elapsed = std::chrono::duration<double>(now - w.methodStart).count();
      ++w.rounds;
      const bool due = w.rounds <= kAlwaysPublishedRounds || stepping || method.done() ||
                       sincePublish >= publishInterval(elapsed, w.lastSnapshotCost);
      if (!due) return;
      const auto snapshotStart = std::chrono::steady_clock::now();
      r.snapshot = method.snapshot(true, &cancelRound_);
      w.lastSnapshotCost =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - snapshotStart).count();
      w.lastPublish = std::chrono::steady_clock::now();
      if (cancelRound_) r.snapshot.reset();  // cut short: it belongs to the old method
    });
    if (r.snapshot && request.inspectX >= 0)
      r.inspection =
          std::make_shared<PixelInspection>(method.inspect(request.inspectX, request.inspectY));
    r.finished = method.done();
  } catch (const std::exception& e) {
    r.failure = e.what();
  }
  return r;
}

void RenderSession::worker() {
  Worker w(threads_);
  std::unique_ptr<BackgroundObserver> observer;
  if (background_) {
    lowerThreadPriority();
    observer = std::make_unique<BackgroundObserver>(w.arena);
  }
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [&] {
      return quit_ || state_ == State::Running || (inspectPending_ && w.method) || publishPending_;
    });
    if (quit_) return;
    if (state_ != State::Running) {
      serveIdle(w, lock);
      continue;
    }
    if (stepsLeft_ == 0) {
      state_ = State::Paused;
      idle_.notify_all();
      releaseWhileIdle(lock);
      continue;
    }
    const RoundRequest request{generation_, factory_,   inspectX_,
                               inspectY_,   stepsLeft_, mapsWanted_};
    cancelRound_ = false;
    lock.unlock();
    RoundResult r = runRound(w, request);
    lock.lock();
    if (request.generation != generation_) {
      // Restarted or cancelled meanwhile: this round's result belongs to the old method, which
      // goes now (its round has returned).
      r = RoundResult{};
      lock.unlock();
      w.drop();
      lock.lock();
      continue;
    }
    if (!r.failure.empty()) {
      state_ = State::Failed;
      error_ = r.failure;
      lock.unlock();
      w.drop();
      lock.lock();
      idle_.notify_all();
      continue;
    }
    const bool published = r.snapshot != nullptr;
    // A round whose snapshot the throttle skipped is published once the session pauses, so
    // a paused view shows every sample traced (and a step then adds exactly one round).
    publishPending_ = !published && !r.finished;
    if (published) {
      publishLocked(std::move(r.snapshot), request.generation);
    }
    if (r.inspection && request.inspectX == inspectX_ && request.inspectY == inspectY_) {
      inspection_ = std::move(r.inspection);
      ++inspectionVersion_;
      inspectPending_ = false;
    }
    if (r.finished) {
      state_ = State::Finished;
      idle_.notify_all();
      releaseWhileIdle(lock);
    } else if (stepsLeft_ > 0) {
      --stepsLeft_;
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
