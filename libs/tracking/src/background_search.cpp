#include <quasiloc/tracking/background_search.h>

#include <quasiloc/core/error.h>

#include <iostream>

namespace quasiloc::tracking
{
BackgroundSearch::~BackgroundSearch()
{
    worker_.waitForError();
    starter_.deferConsole(false);
}

void BackgroundSearch::begin(const std::string& label, const std::optional<SearchPrior>& prior, bool single_fix,
                             const std::optional<HeadingPrior>& heading)
{
    core::require(!searching_, "BackgroundSearch", "begin() while a search is under way");
    worker_.wait();
    starter_.begin(label, prior, single_fix, heading);
    queue_.clear();
    found_.reset();
    result_.reset();
    searching_ = true;
}

void BackgroundSearch::push(const dataset::StereoFrame& frame, const std::optional<OdometryPrediction>& odometry)
{
    if (searching_) queue_.emplace_back(frame, odometry);
}

void BackgroundSearch::collectAndStart()
{
    if (!searching_ || !worker_.idle()) return;
    worker_.wait();  // idle: returns at once, rethrows the search's error
    starter_.console() << starter_.takeConsole() << std::flush;
    if (found_)
    {
        result_ = std::move(found_);
        found_.reset();
        searching_ = false;
        queue_.clear();
        return;
    }
    if (queue_.empty()) return;
    batch_.assign(std::make_move_iterator(queue_.begin()), std::make_move_iterator(queue_.end()));
    queue_.clear();
    worker_.start([this] {
        for (size_t i = 0; i < batch_.size(); ++i)
            if (auto start = starter_.feed(batch_[i].first, !latest_only_ || i + 1 == batch_.size(), batch_[i].second))
            {
                found_ = std::move(start);
                break;
            }
        batch_.clear();
    });
}

std::optional<GlobalInitialState> BackgroundSearch::poll()
{
    collectAndStart();
    auto r = std::move(result_);
    result_.reset();
    return r;
}

std::optional<GlobalInitialState> BackgroundSearch::finish()
{
    while (searching_)
    {
        worker_.wait();
        collectAndStart();
        if (result_ || (worker_.idle() && queue_.empty())) break;
    }
    auto r = std::move(result_);
    result_.reset();
    return r;
}

}  // namespace quasiloc::tracking
