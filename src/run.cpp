#include "pbf/run.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <nlohmann/json.hpp>
#include <system_error>

#include "pbf/io.hpp"
#include "pbf/version.hpp"

namespace pbf {

std::string statsCsvHeader() {
    return "frame,time,particles,substeps,iterations,step_ms,avg_density_error,max_density_error,"
           "kinetic_energy,escaped,inside_solid,max_speed,neighbor_ms,solve_ms,post_ms";
}

std::string statsCsvRow(const FrameReport& r) {
    const double perStep = r.substeps > 0 ? 1.0 / r.substeps : 0.0;
    return fmt::format(
        "{},{:.6f},{},{},{},{:.4f},{:.6e},{:.6e},{:.6e},{},{},{:.5f},{:.4f},{:.4f},{:.4f}", r.frame,
        r.time, r.state.particles, r.substeps, r.iterations, r.stepMs, r.state.averageDensityError,
        r.state.maxDensityError, r.state.kineticEnergy, r.state.escaped, r.state.insideSolid,
        r.state.maxSpeed, r.stageMs.neighborSearch * perStep, r.stageMs.solve * perStep,
        (r.stageMs.predict + r.stageMs.postProcess) * perStep);
}

std::filesystem::path frameFileName(int frame) {
    return fmt::format("frame_{:05d}.ply", frame);
}

namespace {

void writeSummary(const std::filesystem::path& file, const Scene& scene, const RunSummary& s) {
    nlohmann::json j;
    j["pbf_version"] = kVersion;
    j["scene"] = scene.name;
    j["scene_file"] = scene.source;
    j["frames"] = s.frames;
    j["particle_radius"] = scene.simulation.particleRadius;  // read by `pbf mesh`
    j["particles"] = s.particles;
    j["simulated_seconds"] = s.simulatedSeconds;
    j["wall_seconds"] = s.wallSeconds;
    j["substeps"] = s.substeps;
    j["particle_steps_per_second"] = s.particleStepsPerSecond;
    j["max_density_error"] = s.maxDensityError;
    j["average_density_error"] = s.averageDensityError;
    j["max_escaped"] = s.maxEscaped;
    j["max_inside_solid"] = s.maxInsideSolid;
    j["skipped_in_solids"] = s.skippedInSolids;
    writeFileAtomically(file, [&](std::ostream& out) { out << j.dump(2) << "\n"; });
}

}  // namespace

RunSummary runScene(const Scene& scene, const RunOptions& options) {
    RunSummary summary;
    std::error_code ec;
    std::filesystem::create_directories(options.outputDirectory, ec);
    if (ec || !std::filesystem::is_directory(options.outputDirectory))
        throw IoError(options.outputDirectory.string() + ": cannot create output directory" +
                      (ec ? " (" + ec.message() + ")" : ""));

    Simulation simulation(scene);
    summary.skippedInSolids = simulation.skippedParticles();
    if (options.onStart) options.onStart(simulation);
    const auto start = std::chrono::steady_clock::now();
    std::string csv = statsCsvHeader() + "\n";
    double densityErrorSum = 0.0;
    auto record = [&](const FrameReport& report) {
        if (options.writeParticles)
            writeParticlesPly(options.outputDirectory / frameFileName(report.frame),
                              simulation.particles());
        if (options.writeFrame) options.writeFrame(report.frame, simulation.particles());
        csv += statsCsvRow(report) + "\n";
        writeFileAtomically(options.outputDirectory / "stats.csv",
                            [&](std::ostream& out) { out << csv; });
        summary.maxDensityError = std::max(summary.maxDensityError, report.state.maxDensityError);
        summary.maxEscaped = std::max(summary.maxEscaped, report.state.escaped);
        summary.maxInsideSolid = std::max(summary.maxInsideSolid, report.state.insideSolid);
        densityErrorSum += report.state.averageDensityError;
        summary.substeps += report.substeps;
        summary.particles = report.state.particles;
        if (options.onFrame) options.onFrame(report);
    };

    record(simulation.report());
    double solverMs = 0.0;
    for (int f = 0; f < options.frames; ++f) {
        const FrameReport report = simulation.advanceFrame();
        solverMs += report.stageMs.total;
        record(report);
    }
    summary.frames = options.frames;
    summary.simulatedSeconds = simulation.time();
    summary.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    summary.averageDensityError = densityErrorSum / (options.frames + 1);
    summary.particleStepsPerSecond =
        solverMs > 0.0 ? double(summary.particles) * double(summary.substeps) / (solverMs * 1e-3)
                       : 0.0;
    writeSummary(options.outputDirectory / "summary.json", scene, summary);
    return summary;
}

}  // namespace pbf
