// libFuzzer harness: see fuzz_targets.hpp (pbf::fuzz::checkpoint) for what one input does.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_targets.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    pbf::fuzz::checkpoint(std::string_view(reinterpret_cast<const char*>(data), size));
    return 0;
}
