// OrderedTasks: tasks are claimed in the order they were added; wait() helps with queued tasks, up to a limit when
// one is given; errors reach the waiting thread.
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

TEST(OrderedTasks, HelpStopsBelowTheGivenTask)
{
    OrderedTasks tasks;
    std::atomic<bool> release{false};
    std::vector<int> ran_here;
    const size_t slow = tasks.add([&release] {
        while (!release) std::this_thread::yield();
    });
    tasks.add([&ran_here] { ran_here.push_back(1); });
    const size_t reserved = tasks.add([&ran_here] { ran_here.push_back(2); });
    std::thread other([&tasks] { tasks.runNext(); });  // claims the slow task (or this thread does, below: the
    std::this_thread::sleep_for(std::chrono::milliseconds(20));  // outcome is the same)
    std::thread releaser([&release] {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        release = true;
    });
    tasks.wait(slow, true, reserved);  // helps with task 1, not with task 2
    EXPECT_EQ(ran_here, (std::vector<int>{1}));
    EXPECT_FALSE(tasks.done(reserved));
    other.join();
    releaser.join();
    tasks.waitAll();
    EXPECT_EQ(ran_here, (std::vector<int>{1, 2}));
}

TEST(OrderedTasks, ATasksErrorReachesTheWaiter)
{
    OrderedTasks tasks;
    const size_t bad = tasks.add([] { throw std::runtime_error("task failed"); });
    tasks.add([] {});
    EXPECT_THROW(tasks.wait(bad), std::runtime_error);
    EXPECT_THROW(tasks.waitAll(), std::runtime_error);
}
