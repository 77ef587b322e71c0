// Independent runs side by side (src/validate/concurrent.hpp).
#include "validate/concurrent.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "pbf/core/threading.hpp"

namespace pbf::validation::detail {
namespace {

// Sets the thread count for one test and restores it.
class Threads {
  public:
    explicit Threads(int threads) : before_(threadCount()) { setThreadCount(threads); }
    ~Threads() { setThreadCount(before_); }

  private:
    int before_;
};

// Catches results stored in the order the tasks finish rather than by
// index (the later tasks here finish first).
TEST(Concurrently, ResultsComeInTheTasksOrder) {
    const Threads threads(2);
    const std::vector<std::string> results = concurrently(6, [](std::size_t k) {
        std::this_thread::sleep_for(std::chrono::milliseconds(5 * (6 - k)));
        return std::to_string(k * k);
    });
    EXPECT_EQ(results, (std::vector<std::string>{"0", "1", "4", "9", "16", "25"}));
}

// Catches tasks run one after another: each of two tasks waits (up to 20 s)
// until the other has started, which only tasks side by side can do.
TEST(Concurrently, RunsTasksSideBySide) {
    const Threads threads(2);
    std::atomic<int> started{0};
    const std::vector<int> sawTheOther = concurrently(2, [&](std::size_t) {
        ++started;
        const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(20);
        while (started.load() < 2 && std::chrono::steady_clock::now() < until)
            std::this_thread::sleep_for(std::chrono::milliseconds(1));
        return int(started.load() == 2);
    });
    EXPECT_EQ(sawTheOther, (std::vector<int>{1, 1}));
}

// Catches an exception lost (a result left default) or escaping a thread
// (std::terminate): the lowest index's is rethrown after all tasks ran.
TEST(Concurrently, RethrowsTheFirstTasksException) {
    const Threads threads(2);
    std::atomic<int> ran{0};
    try {
        concurrently(6, [&](std::size_t k) {
            ++ran;
            if (k == 2 || k == 4) throw std::runtime_error("task " + std::to_string(k));
            return 0;
        });
        ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
        EXPECT_EQ(std::string(e.what()), "task 2");
    }
    EXPECT_EQ(ran.load(), 6);
}

// Catches progress messages passed on from two tasks at once (the
// forwarding function here is not reentrant, as printing a line is not).
TEST(SerialProgress, PassesOnOneMessageAtATime) {
    const Threads threads(2);
    std::atomic<bool> inside{false};
    std::atomic<int> overlaps{0}, messages{0};
    Options options;
    options.progress = [&](const std::string&) {
        if (inside.exchange(true)) ++overlaps;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        ++messages;
        inside = false;
    };
    const SerialProgress progress(options);
    concurrently(2, [&](std::size_t) {
        for (int k = 0; k < 30; ++k) progress.options().progress("message");
        return 0;
    });
    EXPECT_EQ(messages.load(), 60);
    EXPECT_EQ(overlaps.load(), 0);
}

}  // namespace
}  // namespace pbf::validation::detail
