// A pbf::World as Python holds it: the world and a mutex.
//
// step_frame() releases the GIL so that other Python threads run while the
// solver works; one of those threads may then touch the same world (read
// its positions, change a setting). The mutex makes every access wait for
// the frame in progress. Whoever waits for the mutex has released the GIL
// first, so a thread that holds the mutex and wants the GIL back cannot
// deadlock with one that holds the GIL and wants the mutex.
#pragma once

#include <pybind11/pybind11.h>

#include <mutex>
#include <utility>

#include "pbf/world/world.hpp"

namespace pbf::python {

class WorldHandle {
  public:
    explicit WorldHandle(World world) : world_(std::move(world)) {}

    // f(world) with the GIL held and the world to itself.
    template <class F>
    decltype(auto) locked(F&& f) {
        std::unique_lock lock(mutex_, std::defer_lock);
        {
            pybind11::gil_scoped_release release;
            lock.lock();
        }
        return f(world_);
    }

    // f(world) with the GIL released (f must not touch Python objects).
    template <class F>
    decltype(auto) unlocked(F&& f) {
        pybind11::gil_scoped_release release;
        std::lock_guard lock(mutex_);
        return f(world_);
    }

  private:
    World world_;
    std::mutex mutex_;
};

}  // namespace pbf::python
