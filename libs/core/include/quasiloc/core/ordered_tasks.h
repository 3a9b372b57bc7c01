#pragma once
// A frame's independent tasks, shared by two threads in the order they were added: each thread claims the next
// unclaimed task and runs it, so a thread that reaches a point where it must wait for one result does useful work
// meanwhile instead (the tracker's measurement stage, frame_measurement.h). A thread that needs one result at a
// known point can claim that task ahead of its turn (runOrWait). Who runs a task changes only when it finishes,
// never what it computes.
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <vector>

namespace quasiloc::core
{
class OrderedTasks
{
   public:
    /** Adds a task (before any thread runs them); returns its number for wait(). */
    size_t add(std::function<void()> task)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        tasks_.push_back({std::move(task), State::Queued, nullptr});
        return tasks_.size() - 1;
    }

    /** Claims the next queued task and runs it on this thread. False when none is left to claim. An exception
     *  is kept for wait(), never thrown here (the worker thread must not lose it). */
    bool runNext()
    {
        std::function<void()> task;
        size_t i = 0;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            while (next_ < tasks_.size() && tasks_[next_].state != State::Queued) ++next_;  // claimed out of order
            if (next_ == tasks_.size()) return false;
            i = next_++;
            task = claim(i);
        }
        execute(i, task);
        return true;
    }

    /** Task i now on this thread, ahead of its turn, if no thread has claimed it yet; else waits for it. For a
     *  result one thread needs at a known point (the camera's edge field, after the map's render). Rethrows what
     *  task i threw. */
    void runOrWait(size_t i)
    {
        std::function<void()> task;
        {
            std::lock_guard<std::mutex> lock(mutex_);
            if (tasks_.at(i).state == State::Queued) task = claim(i);
        }
        if (task) execute(i, task);
        wait(i);
    }

    bool done(size_t i)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return tasks_.at(i).state == State::Done;
    }

    /** Until task i has finished: runs other queued tasks on this thread while task i is still queued or while
     *  `help` and another task is queued, then blocks. Rethrows what task i threw. */
    void wait(size_t i, bool help = false)
    {
        while (!done(i) && (help || queued(i)) && runNext())
        {}
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [&] { return tasks_.at(i).state == State::Done; });
        if (tasks_[i].error) std::rethrow_exception(tasks_[i].error);
    }

    /** Runs what is left here, waits for the rest, and rethrows the first exception of any task. */
    void waitAll()
    {
        while (runNext())
        {}
        std::unique_lock<std::mutex> lock(mutex_);
        finished_.wait(lock, [&] {
            for (const Task& t : tasks_)
                if (t.state != State::Done) return false;
            return true;
        });
        for (const Task& t : tasks_)
            if (t.error) std::rethrow_exception(t.error);
    }

   private:
    enum class State
    {
        Queued,
        Running,
        Done
    };
    struct Task
    {
        std::function<void()> run;
        State state;
        std::exception_ptr error;
    };
    bool queued(size_t i)
    {
        std::lock_guard<std::mutex> lock(mutex_);
        return tasks_.at(i).state == State::Queued;
    }
    /** Marks task i running and takes its function (the caller holds the lock). */
    std::function<void()> claim(size_t i)
    {
        tasks_[i].state = State::Running;
        return std::move(tasks_[i].run);
    }
    /** Runs the claimed task i; an exception is kept for wait(). */
    void execute(size_t i, std::function<void()>& task)
    {
        std::exception_ptr error;
        try
        {
            task();
        }
        catch (...)
        {
            error = std::current_exception();
        }
        {
            std::lock_guard<std::mutex> lock(mutex_);
            tasks_[i].state = State::Done;
            tasks_[i].error = error;
        }
        finished_.notify_all();
    }

    std::mutex mutex_;
    std::condition_variable finished_;
    std::vector<Task> tasks_;
    size_t next_ = 0;
};

}  // namespace quasiloc::core
