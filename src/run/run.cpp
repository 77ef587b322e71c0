#include "pbf/run.hpp"

#include <fmt/format.h>

#include "run/run_driver.hpp"

namespace pbf {

std::string statsCsvHeader() {
    return "frame,time,particles,substeps,iterations,step_ms,avg_density_error,max_density_error,"
           "kinetic_energy,escaped,inside_solid,max_speed,neighbor_ms,solve_ms,post_ms";
}

std::string statsCsvRow(const FrameReport& r) {
    const double perStep = r.substeps > 0 ? 1.0 / r.substeps : 0.0;
    return fmt::format(
        "{},{:.6f},{},{},{:.2f},{:.4f},{:.6e},{:.6e},{:.6e},{},{},{:.5f},{:.4f},{:.4f},{:.4f}", r.frame,
        r.time, r.state.particles, r.substeps, r.iterations, r.stepMs, r.state.averageDensityError,
        r.state.maxDensityError, r.state.kineticEnergy, r.state.escaped, r.state.insideSolid,
        r.state.maxSpeed, r.stageMs.neighborSearch * perStep, r.stageMs.solve * perStep,
        (r.stageMs.predict + r.stageMs.postProcess) * perStep);
}

std::filesystem::path frameFileName(int frame) {
    return fmt::format("frame_{:05d}.ply", frame);
}

RunSummary runScene(const Scene& scene, const RunOptions& options) {
    detail::RunDriver driver(scene, options);
    return driver.run();
}

}  // namespace pbf
