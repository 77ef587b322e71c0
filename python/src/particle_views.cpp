#include "particle_views.hpp"

#include <memory>
#include <vector>

namespace pbf::python {
namespace py = pybind11;
namespace {

template <class T>
py::array view(const std::shared_ptr<std::vector<T>>& buffer, std::size_t count,
               std::size_t components, bool writable) {
    using Owner = std::shared_ptr<std::vector<T>>;
    py::capsule base(new Owner(buffer), [](void* owner) { delete static_cast<Owner*>(owner); });
    const auto n = static_cast<py::ssize_t>(count);
    std::vector<py::ssize_t> shape{n};
    if (components > 1) shape.push_back(static_cast<py::ssize_t>(components));
    py::array_t<T> array(shape, buffer->data(), base);
    if (!writable) array.attr("setflags")(py::arg("write") = false);
    return array;
}

}  // namespace

py::array positionsView(const ParticleArrays& a) {
    return view(a.position, a.count, 3, true);
}
py::array velocitiesView(const ParticleArrays& a) {
    return view(a.velocity, a.count, 3, true);
}
py::array densitiesView(const ParticleArrays& a) {
    return view(a.density, a.count, 1, false);
}
py::array idsView(const ParticleArrays& a) {
    return view(a.id, a.count, 1, false);
}

}  // namespace pbf::python
