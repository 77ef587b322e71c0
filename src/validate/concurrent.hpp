// Independent runs of one case side by side (private header).
//
// The surface-tension cases run many small drops: rayleigh_drop 12-24
// samplings of the lattice per resolution, laplace and wetting several
// drops. A drop of a few thousand particles is one or two of the solver's
// blocks of 1024 (core/parallel.hpp), so it keeps one core busy however many
// threads the run has. concurrently() runs such drops side by side instead,
// one per thread; inside a task the solver's own parallel loops then run on
// that task's thread alone (OpenMP does not nest by default), and since
// every run gives the same bits at any thread count, the results are those
// of running the tasks one after another.
#pragma once

#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "pbf/core/threading.hpp"
#include "pbf/validate/validate.hpp"

namespace pbf::validation::detail {

// Results of task(0) .. task(count - 1), in that order, run on up to
// threadCount() threads at once. An exception a task throws is rethrown
// here after every task has ended (the lowest index's, if several threw).
template <class Task>
auto concurrently(std::size_t count, Task&& task) {
    using Result = decltype(task(std::size_t{0}));
    std::vector<Result> results(count);
    std::vector<std::exception_ptr> errors(count);
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(count);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threadCount()) if (count > 1)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
        try {
            results[std::size_t(k)] = task(std::size_t(k));
        } catch (...) {
            errors[std::size_t(k)] = std::current_exception();
        }
    }
    for (const std::exception_ptr& error : errors)
        if (error) std::rethrow_exception(error);
    return results;
}

// Options whose progress messages may come from concurrent tasks: each one
// is passed on whole, one at a time (their order is the tasks' finishing
// order).
class SerialProgress {
  public:
    explicit SerialProgress(const Options& options) : options_(options) {
        if (options.progress)
            options_.progress = [this, forward = options.progress](const std::string& message) {
                const std::lock_guard<std::mutex> lock(mutex_);
                forward(message);
            };
    }
    SerialProgress(const SerialProgress&) = delete;
    SerialProgress& operator=(const SerialProgress&) = delete;
    const Options& options() const { return options_; }

  private:
    Options options_;
    std::mutex mutex_;
};

}  // namespace pbf::validation::detail
