// OrderedTasks: tasks are claimed in the order they were added; wait() helps with queued tasks; errors reach the
// waiting thread.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <quasiloc/core/ordered_tasks.h>
#include <stdexcept>
#include <thread>
#include <vector>

using quasiloc::core::OrderedTasks;

TEST(OrderedTasks, WaitRunsQueuedTasksInOrderOnThisThread)
{
    OrderedTasks tasks;
    std::vector<int> order;
    for (int k = 0; k < 4; ++k) tasks.add([&order, k] { order.push_back(k); });
    tasks.wait(2);  // task 2 is queued: tasks 0..2 run here, 3 stays queued
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2}));
    EXPECT_FALSE(tasks.done(3));
    tasks.waitAll();
    EXPECT_EQ(order, (std::vector<int>{0, 1, 2, 3}));
}

TEST(OrderedTasks, HelpRunsLaterQueuedTasksWhileTheAwaitedOneRunsElsewhere)
{
    OrderedTasks tasks;
    std::atomic<bool> started{false}, release{false};
    std::vector<int> ran_here;
    const size_t slow = tasks.add([&started, &release] {
        started = true;
        while (!release) std::this_thread::yield();
    });
    tasks.add([&ran_here] { ran_here.push_back(1); });
    tasks.add([&ran_here] { ran_here.push_back(2); });
    std::thread other([&tasks] { tasks.runNext(); });  // claims the slow task
    while (!started) std::this_thread::yield();
    std::thread releaser([&release] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        release = true;
    });
    tasks.wait(slow, true);
    EXPECT_EQ(ran_here, (std::vector<int>{1, 2}));
    other.join();
    releaser.join();
    tasks.waitAll();
}

TEST(OrderedTasks, ATasksErrorReachesTheWaiter)
{
    OrderedTasks tasks;
    const size_t bad = tasks.add([] { throw std::runtime_error("task failed"); });
    tasks.add([] {});
    EXPECT_THROW(tasks.wait(bad), std::runtime_error);
    EXPECT_THROW(tasks.waitAll(), std::runtime_error);
}

TEST(OrderedTasks, RunOrWaitClaimsATaskAheadOfItsTurnAndTheOthersSkipIt)
{
    OrderedTasks tasks;
    std::vector<int> order;
    tasks.add([&order] { order.push_back(0); });
    tasks.add([&order] { order.push_back(1); });
    const size_t last = tasks.add([&order] { order.push_back(2); });
    tasks.runOrWait(last);  // queued: runs now, on this thread
    EXPECT_EQ(order, (std::vector<int>{2}));
    tasks.waitAll();  // the rest in their order, the claimed one not again
    EXPECT_EQ(order, (std::vector<int>{2, 0, 1}));
}

TEST(OrderedTasks, RunOrWaitWaitsForATaskAnotherThreadClaimed)
{
    OrderedTasks tasks;
    std::atomic<bool> started{false}, release{false};
    std::atomic<int> runs{0};
    const size_t slow = tasks.add([&] {
        started = true;
        ++runs;
        while (!release) std::this_thread::yield();
    });
    std::thread other([&tasks] { tasks.runNext(); });
    while (!started) std::this_thread::yield();
    std::thread releaser([&release] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        release = true;
    });
    tasks.runOrWait(slow);
    EXPECT_TRUE(tasks.done(slow));
    EXPECT_EQ(runs.load(), 1);
    other.join();
    releaser.join();
}
