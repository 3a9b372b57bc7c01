#pragma once
// One helper thread that runs one task at a time (the front-end's line branch, the tracker's stereo extraction).
// It lives as long as its owner: a thread per image would fault its stack pages in again and register with
// OpenCV's TBB pool every time (measured in the tracker: a std::async per frame made the stages it overlapped
// slower than running them in turn).
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>

namespace quasiloc::core
{
class WorkerThread
{
   public:
    WorkerThread() : thread_([this] { loop(); }) {}
    ~WorkerThread()
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            stop_ = true;
        }
        wake_.notify_all();
        thread_.join();
    }
    WorkerThread(const WorkerThread&) = delete;
    WorkerThread& operator=(const WorkerThread&) = delete;

    /** Starts `task`; the previous one must have been waited for. */
    void start(std::function<void()> task)
    {
        {
            std::lock_guard<std::mutex> lock(mutex_);
            task_ = std::move(task);
            done_ = false;
            error_ = nullptr;
        }
        wake_.notify_all();
    }
    /** True when no task is running (the last one, if any, has finished: wait() then returns at once). */
    bool idle()
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return done_;
    }
    /** Waits for the task started last (returns at once if none is running) and rethrows what it threw. */
    void wait()
    {
        if (const std::exception_ptr error = waitForError()) std::rethrow_exception(error);
    }
    /** Waits like wait() but returns what the task threw (nullptr: nothing), e.g. while another exception is
     *  already on its way. */
    std::exception_ptr waitForError()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [this] { return done_; });
        std::exception_ptr error = error_;
        error_ = nullptr;
        return error;
    }

   private:
    void loop()
    {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;)
        {
            wake_.wait(lock, [this] { return stop_ || bool(task_); });
            if (!task_) return;  // stop_
            auto task = std::move(task_);
            task_ = nullptr;
            lock.unlock();
            std::exception_ptr error;
            try
            {
                task();
            }
            catch (...)
            {
                error = std::current_exception();
            }
            lock.lock();
            error_ = error;
            done_ = true;
            finished_.notify_all();
        }
    }

    std::mutex mutex_;
    std::condition_variable wake_, finished_;
    std::function<void()> task_;
    bool done_ = true, stop_ = false;
    std::exception_ptr error_;
    std::thread thread_;  // last: starts after the members it uses exist
};

}  // namespace quasiloc::core
