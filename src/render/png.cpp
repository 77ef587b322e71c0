// PNG files through stb_image_write (Debian libstb-dev ships the compiled library).
#include <stb_image_write.h>

#include <vector>

#include "pbf/io/io.hpp"
#include "pbf/render/headless.hpp"

namespace pbf::render {
namespace {

void appendBytes(void* context, void* data, int size) {
    auto* bytes = static_cast<std::vector<char>*>(context);
    const char* begin = static_cast<const char*>(data);
    bytes->insert(bytes->end(), begin, begin + size);
}

}  // namespace

void writePng(const std::filesystem::path& path, const Image& image) {
    std::vector<char> bytes;
    if (stbi_write_png_to_func(appendBytes, &bytes, image.width, image.height, 4, image.rgba.data(),
                               image.width * 4) == 0)
        throw IoError(path.string() + ": cannot encode PNG");
    writeFileAtomically(
        path, [&](std::ostream& out) { out.write(bytes.data(), std::streamsize(bytes.size())); });
}

}  // namespace pbf::render
