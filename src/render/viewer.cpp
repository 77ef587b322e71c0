#include "pbf/render/viewer.hpp"

#include "pbf/render/headless.hpp"

namespace pbf::render {
ViewerSummary runViewer(const Scene&, const ViewerOptions&) { throw RenderError("viewer: not built yet"); }
}  // namespace pbf::render
