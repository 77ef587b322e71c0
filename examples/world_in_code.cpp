// A water column collapsing in a tank, built in code with pbf::World (the
// README's C++ example): prints the surge front against time, in the
// dimensionless units of Martin & Moyce 1952 (front x / column width a
// against t sqrt(2 g / a)).
//
//   build/release/examples/pbf_example_world [frames]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "pbf/world/world.hpp"

int main(int argc, char** argv) {
    const int frames = argc > 1 ? std::atoi(argv[1]) : 30;
    const float a = 0.2f;  // column width and depth ratio 1:2 (height 2a), as Martin & Moyce

    pbf::WorldDef def;  // SI units; every field has a documented default
    def.name = "column";
    def.simulation.domain = {{0, 0, 0}, {1.0f, 0.6f, 0.1f}};
    def.simulation.particleRadius = 0.005f;
    def.fluidBlocks.push_back({{{0, 0, 0}, {a, 2 * a, 0.1f}}, {0, 0, 0}});
    def.fps = 60.0f;

    pbf::World world(def);
    std::printf("%zu particles\n%6s %8s %10s %12s\n", world.particleCount(), "frame", "t (s)",
                "T=t*sqrt(2g/a)", "front Z=x/a");
    for (int f = 0; f < frames; ++f) {
        const pbf::FrameResult r = world.stepFrame();
        if (!r.ok()) {
            std::fprintf(stderr, "%s\n", r.error->message.c_str());
            return 4;
        }
        const pbf::ParticleArrays& p = world.arraysById();
        float front = 0.0f;
        for (std::size_t k = 0; k < p.count; ++k) front = std::max(front, (*p.position)[3 * k]);
        std::printf("%6d %8.4f %10.3f %12.3f\n", r.report.frame, r.report.time,
                    r.report.time * std::sqrt(2.0 * 9.81 / a), front / a);
    }
    return 0;
}
