// world.settings: a live view of World::settings() whose attributes write
// through World::applySettings, so every change is validated by the C++
// library (pbf.SceneError naming the field; nothing changes on error) and
// takes effect at the next step.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>

#include "world_handle.hpp"

namespace pbf::python {

class Settings {
  public:
    explicit Settings(std::shared_ptr<WorldHandle> world) : world_(std::move(world)) {}
    WorldHandle& world() const { return *world_; }

  private:
    std::shared_ptr<WorldHandle> world_;
};

// Applies `changes` ({attribute or scene path: value}) in one
// applySettings call: all or nothing.
void updateSettings(WorldHandle& world, const pybind11::dict& changes);

}  // namespace pbf::python
