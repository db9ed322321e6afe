// A render session: runs a progressive method's rounds on a worker thread and publishes a
// snapshot after each round, so a viewer only has to draw the latest one. The caller's
// thread never waits for a round: every call here returns at once (except wait()).
//
// Control: start, pause (after the round in flight), resume, step (one round, then
// pause), cancel (the round in flight stops at its next safe point), and restart with a
// new method (on a camera or parameter change: the old round is cancelled and the new
// method starts from its coarse pass).
#pragma once

#include "methods/progressive.h"

#include <atomic>
#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

namespace penumbra {

class RenderSession {
 public:
  // Builds the method to run; called on the worker thread at every (re)start.
  using MethodFactory = std::function<std::unique_ptr<ProgressiveMethod>()>;

  enum class State { Idle, Running, Paused, Finished, Cancelled, Failed };

  // threads: worker threads for the rounds (0 = all cores). background: run the rounds at a
  // lower scheduling priority (nice +10), so that an interactive thread on the same cores
  // (the viewer's UI, a software GL rasteriser) keeps its frame rate; throughput only drops
  // by what that thread uses.
  explicit RenderSession(int threads = 0, bool background = false);
  ~RenderSession();  // cancels and joins
  RenderSession(const RenderSession&) = delete;
  RenderSession& operator=(const RenderSession&) = delete;

  // From scratch, running; with rounds >= 0 it pauses after that many rounds (a headless
  // screenshot after exactly N rounds).
  // Returns the generation of this start: latest() tells which generation a snapshot is of.
  uint64_t start(MethodFactory factory, int rounds = -1);
  uint64_t restart(MethodFactory factory, int rounds = -1);  // as start: cancels what runs
  void pause();
  void resume();
  void step();  // runs one round, then pauses
  void cancel();

  State state() const;
  std::string error() const;  // the exception message when the state is Failed
  // The latest published snapshot (null before the first round completes) and a counter
  // that increases with every publication.
  // With `generation`, also the start the snapshot belongs to (a snapshot of the method
  // before a restart may be the latest for a moment after it, published by a round that
  // finished just as it restarted). A (re)start releases the session's latest snapshot: null
  // until the new method publishes its first.
  std::shared_ptr<const Snapshot> latest(uint64_t* generation = nullptr) const;
  uint64_t version() const { return version_.load(); }
  // Asks for the inspection of pixel (x, y) (-1, -1: none). It is taken after every round,
  // and at once when no round runs; the method also records that pixel's candidates.
  void inspect(int x, int y);
  std::shared_ptr<const PixelInspection> inspection() const;  // null until one is taken
  // Whether snapshots carry the method's debug maps (true by default; a viewer that shows no
  // overlay turns them off: ProgressiveMethod::setMapsWanted). Turned on while no round runs
  // and the latest snapshot has none, it publishes that round again with its maps; while
  // rounds run, the next published snapshot has them.
  void setMapsWanted(bool wanted);
  uint64_t inspectionVersion() const { return inspectionVersion_.load(); }

  // Called on the worker thread, with the session's lock held, each time a snapshot is
  // published (latest() has a new one): a window wakes its event loop with it, so that a new
  // picture is drawn at once rather than at the loop's next look. It must not call the session.
  void setOnPublish(std::function<void()> onPublish);

  // Blocks until the session is not Running (paused, finished, cancelled or failed) or
  // `timeoutSeconds` pass; returns whether it stopped running.
  bool wait(double timeoutSeconds = 1e30);

 private:
  struct Worker;
  // What a round of the worker needs from the session, read under the lock.
  struct RoundRequest {
    uint64_t generation;
    MethodFactory factory;
    int inspectX, inspectY;
    int stepsLeft;
    bool mapsWanted;
  };
  struct RoundResult {
    std::shared_ptr<Snapshot> snapshot;  // null when the publishing rule skipped it
    std::shared_ptr<PixelInspection> inspection;
    bool finished = false;
    std::string failure;
  };
  void worker();
  // Without the lock: (re)makes the method when the generation changed, runs one round and
  // takes its snapshot when the publishing rule says so.
  RoundResult runRound(Worker& worker, const RoundRequest& request);
  // With the lock held (released while the method works): a paused or finished session
  // publishes the round the throttle skipped, and takes an inspection asked for.
  void serveIdle(Worker& worker, std::unique_lock<std::mutex>& lock);
  // Gives the memory kept for the next round back while the session pauses or finishes.
  static void releaseWhileIdle(std::unique_lock<std::mutex>& lock);
  // Makes `snapshot` the latest (mutex_ held) and tells the onPublish callback.
  void publishLocked(std::shared_ptr<const Snapshot> snapshot, uint64_t generation);
  void takeInspection(Worker& worker, std::unique_lock<std::mutex>& lock);

  int threads_;
  bool background_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;  // to the worker: a command arrived
  std::condition_variable idle_;  // to waiters: the state left Running
  MethodFactory factory_;
  uint64_t generation_ = 0;  // incremented by every start
  State state_ = State::Idle;
  int stepsLeft_ = -1;  // -1: run freely; n >= 0: rounds before pausing
  bool quit_ = false;
  std::string error_;
  std::atomic<bool> cancelRound_{false};
  std::shared_ptr<const Snapshot> latest_;
  std::function<void()> onPublish_;  // (guarded by mutex_)
  uint64_t latestGeneration_ = 0;
  std::atomic<uint64_t> version_{0};
  int inspectX_ = -1, inspectY_ = -1;
  bool inspectPending_ = false;  // a new pixel was asked for
  bool publishPending_ = false;  // a round ran whose snapshot the throttle skipped
  bool mapsWanted_ = true;
  std::shared_ptr<const PixelInspection> inspection_;
  std::atomic<uint64_t> inspectionVersion_{0};
  std::thread thread_;
};

const char* toString(RenderSession::State state);

// The publishing rule of a running session: seconds from one published snapshot to the next,
// `elapsed` seconds after the method's start, the last snapshot having cost `lastCost` seconds.
// At least a fifth of a second; for the first four seconds the last snapshot's cost (the
// pictures right after a move come as fast as the reconstruction allows); then a growing
// multiple of it, up to 6 (snapshots take at most a seventh of a long run's time).
double publishInterval(double elapsed, double lastCost);

}  // namespace penumbra
