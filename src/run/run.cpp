#include "pbf/run/run.hpp"

#include <fmt/format.h>

#include "run/run_driver.hpp"

namespace pbf {

std::string statsCsvHeader() {
    return "frame,time,particles,substeps,iterations,step_ms,avg_density_error,max_density_error,"
           "kinetic_energy,escaped,inside_solid,max_speed,neighbor_ms,solve_ms,post_ms,emitted,"
           "removed";
}

std::string statsCsvRow(const FrameReport& r) {
    const double perStep = r.substeps > 0 ? 1.0 / r.substeps : 0.0;
    return fmt::format(
        "{},{:.6f},{},{},{:.2f},{:.4f},{:.6e},{:.6e},{:.6e},{},{},{:.5f},{:.4f},{:.4f},{:.4f},{},{"
        "}",
        r.frame, r.time, r.state.particles, r.substeps, r.iterations, r.stepMs,
        r.state.averageDensityError, r.state.maxDensityError, r.state.kineticEnergy,
        r.state.escaped, r.state.insideSolid, r.state.maxSpeed, r.stageMs.neighborSearch * perStep,
        r.stageMs.solve * perStep, (r.stageMs.predict + r.stageMs.postProcess) * perStep, r.emitted,
        r.removed);
}

std::string bodiesCsvHeader() {
    return "frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz,fx,fy,fz,tx,ty,tz";
}

// Centre of mass (m; every digit its float has: far from the origin seven
// digits would be centimetres), orientation of the principal axes (unit quaternion),
// linear (m/s) and angular (rad/s) velocity, then the fluid's force (N) and
// torque about the centre of mass (N m) averaged over the frame.
std::string bodiesCsvRows(const World& world) {
    std::string rows;
    const auto& states = world.bodyStates();
    const auto& loads = world.bodyLoads();
    for (std::size_t k = 0; k < states.size(); ++k) {
        const RigidBodyState& b = states[k];
        const RigidBodyLoad& l = loads[k];
        rows += fmt::format(
            "{},{:.6f},{},{},{},{},{:.7g},{:.7g},{:.7g},{:.7g},{:.7g},{:.7g},{:.7g},"
            "{:.7g},{:.7g},{:.7g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g}\n",
            world.frame(), world.time(), k, b.position.x, b.position.y, b.position.z,
            b.orientation.w, b.orientation.x, b.orientation.y, b.orientation.z, b.velocity.x,
            b.velocity.y, b.velocity.z, b.angularVelocity.x, b.angularVelocity.y,
            b.angularVelocity.z, l.force.x, l.force.y, l.force.z, l.torque.x, l.torque.y,
            l.torque.z);
    }
    return rows;
}

std::filesystem::path frameFileName(int frame) {
    return fmt::format("frame_{:05d}.ply", frame);
}

RunSummary runScene(const Scene& scene, const RunOptions& options) {
    detail::RunDriver driver(scene, options);
    return driver.run();
}

}  // namespace pbf
