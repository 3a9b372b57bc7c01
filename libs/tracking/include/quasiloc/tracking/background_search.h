#pragma once
// quasiloc-track's relocalization search on its own thread. After a loss the tracker goes on tracking at its own
// pace while global localization (GlobalStarter::feed: SGBM stereo, the search over candidate positions, the
// appearance check; 0.2-0.6 s per attempt on 2 cores near the last confirmed pose, 0.4-1.3 s over the whole map)
// works on the frames since the loss on a worker thread. No frame waits for an attempt; the start is picked up by
// poll() on a later frame, and every frame since the fix is tracked again from it after a restart (the caller keeps
// them).
//
// When the search falls behind (an attempt takes longer than a frame), latest_only attempts only the newest frame
// of those waiting and gives the older ones to the search for their IMU samples alone: the search stays near the
// present (real time) at the price of depending on the machine's speed (which frames are attempted). Without it
// every frame is attempted in order: the same fixes on every machine, but a search that can fall seconds behind.
//
// Threads: the starter must not be used by anyone else while searching() (its refiner must have a renderer of its
// own); its distance field is only read.
#include <deque>
#include <optional>
#include <quasiloc/core/worker_thread.h>
#include <string>
#include <vector>

#include <quasiloc/tracking/global_start.h>

namespace quasiloc::tracking
{
class BackgroundSearch
{
   public:
    /** The starter's console lines are printed by this thread (in poll/finish). */
    BackgroundSearch(GlobalStarter& starter, bool latest_only) : starter_(starter), latest_only_(latest_only)
    {
        starter_.deferConsole(true);
    }
    ~BackgroundSearch();

    /** Starts a search (GlobalStarter::begin); none may be under way. */
    void begin(const std::string& label, const std::optional<SearchPrior>& prior = std::nullopt,
               bool single_fix = false, const std::optional<HeadingPrior>& heading = std::nullopt);
    bool searching() const { return searching_; }
    /** Queues a frame for the search, with where the odometry puts it (if known); the thread takes the queue
     *  whenever it is idle. */
    void push(const dataset::StereoFrame& frame, const std::optional<OdometryPrediction>& odometry = std::nullopt);
    /** Without waiting: the start, if the thread has found one (the search has then ended). Rethrows what the
     *  search threw. */
    std::optional<GlobalInitialState> poll();
    /** Waits until every queued frame has been searched (or a start found): the start, or nullopt (the search then
     *  stays under way). */
    std::optional<GlobalInitialState> finish();

   private:
    /** Hands the queue to the thread when it is idle; collects a start it found. */
    void collectAndStart();

    GlobalStarter& starter_;
    bool latest_only_ = true;
    using Queued = std::pair<dataset::StereoFrame, std::optional<OdometryPrediction>>;
    std::deque<Queued> queue_;                  // this thread's: frames not yet handed over
    std::vector<Queued> batch_;                 // the worker's while it runs
    std::optional<GlobalInitialState> found_;   // written by the worker, read once it is idle
    std::optional<GlobalInitialState> result_;  // collected, not yet returned
    bool searching_ = false;
    core::WorkerThread worker_;  // last: destroyed (joined) first
};
}  // namespace quasiloc::tracking
