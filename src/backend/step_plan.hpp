// A solver step as a list of named stages (private header, shared by the
// backends), in the manner of Box2D v3's solver stages and Jolt's job list.
//
// A step is three lists of stages over one per-step context: the stages
// before the density iterations, the stages of one iteration (run until the
// iteration control stops them), and the stages after. Every stage has a
// name (`pbf bench` and the docs use it) and the StageTimes phase and part
// its time goes to; one scoped timer per stage does the accounting. A
// backend that wraps another — the MPI backend around the CPU solver —
// inserts its own stages (migration, halo exchanges, global sums) between
// the wrapped solver's stages instead of being called back from inside it.
#pragma once

#include <array>
#include <chrono>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "pbf/backend/backend.hpp"

namespace pbf {

// Every stage any backend runs, in the order a step runs them.
enum class Stage {
    // Before the iterations (Alg. 1 l. 1-7).
    Predict,        // v += dt g; x* = x + dt v
    WarmStart,      // x* += w dt^2 a (solver.warm_start)
    CollideSolids,  // swept collision of x -> x* with the solids
    Distribute,     // MPI: migration to the key ranges' owners, ghosts added
    SortByCell,     // cell of each particle, counting sort
    Reorder,        // every particle field permuted into cell order
    NeighborLists,  // distance tests, neighbour lists
    OwnedRange,     // MPI: which of the sorted particles this process computes
    PackPositions,  // x* into the iterations' packed records
    // One density iteration (Alg. 1 l. 8-19).
    DensityAndLambda,   // rho_i, lambda_i
    ExchangeLambda,     // MPI: ghosts' lambda and density
    CompressionTotals,  // sum of C_i (tolerance mode)
    SumCompression,     // MPI: the sum over all processes
    ConvergenceCheck,   // stop the iterations when the tolerance is met
    CorrectPositions,   // dp_i with s_corr; x* += omega dp; projections
    ExchangePositions,  // MPI: ghosts' corrected x*
    // After the iterations (Alg. 1 l. 20-24).
    UnpackPositions,          // packed records back into x*
    RecordSolveAcceleration,  // a = (x* - x - dt v) / dt^2 (warm start)
    UpdateVelocity,           // v = (x* - x) / dt
    ViscosityAndVorticity,    // XSPH; vorticity omega_i
    ExchangeVorticity,        // MPI: ghosts' omega
    PhysicalViscosity,        // v += dt nu lap v (fluid.kinematic_viscosity)
    VorticityConfinement,     // v += dt f_vorticity
    SurfaceLayer,             // s_i: who is in the surface layer (not a strand)
    ExchangeSurfaceLayer,     // MPI: ghosts' s
    SurfaceTension,           // v += dt a: cohesion of the surface layer, adhesion
    ColourGradient,           // g_i of the curvature force (the surface band)
    ExchangeColourGradient,   // MPI: ghosts' g
    BandNormal,               // nb_i: the band's averaged normals
    ExchangeBandNormal,       // MPI: ghosts' nb
    Curvature,                // kappa_i
    ExchangeCurvature,        // MPI: ghosts' kappa
    CurvatureForce,           // v += dt a: the curvature force
    BoundaryResponse,         // restitution and friction; x = x*
    Collect,                  // MPI: ghosts dropped
    Count
};

// A member of StageTimes. (Through an alias: nvcc writes a plain
// `double StageTimes::*phase` back out with parentheses, which the host
// compiler's -Wparentheses rejects.)
using StageTimesField = double StageTimes::*;

struct StageInfo {
    std::string_view name;  // snake_case, as `pbf bench` prints it
    StageTimesField phase;  // predict, neighborSearch, solve or postProcess
    StageTimesField part;   // a finer part of the phase, or null
};

inline const StageInfo& stageInfo(Stage stage) {
    using T = StageTimes;
    static const std::array<StageInfo, std::size_t(Stage::Count)> kInfo = {{
        {"predict", &T::predict, nullptr},
        {"warm_start", &T::predict, nullptr},
        {"collide_solids", &T::predict, nullptr},
        {"distribute", &T::neighborSearch, &T::exchange},
        {"sort_by_cell", &T::neighborSearch, &T::gridBuild},
        {"reorder", &T::neighborSearch, &T::reorder},
        {"neighbor_lists", &T::neighborSearch, &T::neighborLists},
        {"owned_range", &T::neighborSearch, nullptr},
        {"pack_positions", &T::solve, nullptr},
        {"density_and_lambda", &T::solve, &T::lambda},
        {"exchange_lambda", &T::solve, &T::exchange},
        {"compression_totals", &T::solve, nullptr},
        {"sum_compression", &T::solve, &T::exchange},
        {"convergence_check", &T::solve, nullptr},
        {"correct_positions", &T::solve, &T::deltaP},
        {"exchange_positions", &T::solve, &T::exchange},
        {"unpack_positions", &T::solve, nullptr},
        {"record_solve_acceleration", &T::postProcess, nullptr},
        {"update_velocity", &T::postProcess, nullptr},
        {"viscosity_and_vorticity", &T::postProcess, nullptr},
        {"exchange_vorticity", &T::postProcess, &T::exchange},
        {"physical_viscosity", &T::postProcess, nullptr},
        {"vorticity_confinement", &T::postProcess, nullptr},
        {"surface_layer", &T::postProcess, nullptr},
        {"exchange_surface_layer", &T::postProcess, &T::exchange},
        {"surface_tension", &T::postProcess, nullptr},
        {"colour_gradient", &T::postProcess, nullptr},
        {"exchange_colour_gradient", &T::postProcess, &T::exchange},
        {"band_normal", &T::postProcess, nullptr},
        {"exchange_band_normal", &T::postProcess, &T::exchange},
        {"curvature", &T::postProcess, nullptr},
        {"exchange_curvature", &T::postProcess, &T::exchange},
        {"curvature_force", &T::postProcess, nullptr},
        {"boundary_response", &T::postProcess, nullptr},
        {"collect", &T::postProcess, &T::exchange},
    }};
    return kInfo[std::size_t(stage)];
}

// The part of a per-step context the plan itself uses: a context type
// derives from it.
struct StepProgress {
    int maxIterations = 0;        // corrections at most (IterationControl)
    int corrections = 0;          // corrections run so far this step
    bool stopIterations = false;  // set by a stage: no further correction
};

template <class Context>
struct StageEntry {
    Stage stage;
    std::function<void(Context&)> run;
    // Whether the stage runs this step (empty: always), e.g. the warm start
    // only while solver.warm_start > 0.
    std::function<bool(const Context&)> enabled = {};
};

template <class Context>
class StepPlan {
  public:
    enum class Part { Before, Iteration, After };

    void add(Part part, StageEntry<Context> entry) { list(part).push_back(std::move(entry)); }

    // Inserts `entry` right after (before) the stage `anchor` (throws
    // std::logic_error when the plan has no such stage).
    void insertAfter(Stage anchor, StageEntry<Context> entry) {
        insert(anchor, 1, std::move(entry));
    }
    void insertBefore(Stage anchor, StageEntry<Context> entry) {
        insert(anchor, 0, std::move(entry));
    }

    // The stages of a part, in order (for tests and `pbf bench`).
    std::vector<Stage> stages(Part part) const {
        std::vector<Stage> out;
        for (const StageEntry<Context>& e : list(part)) out.push_back(e.stage);
        return out;
    }

    // Runs one step: the stages before, the iteration's stages until
    // `maxIterations` corrections ran or a stage stopped them, the stages
    // after. `times` is reset and filled (the phases, the parts, `total`,
    // `iterations`: the corrections run).
    void run(Context& context, StageTimes& times) const {
        const auto start = Clock::now();
        times = StageTimes{};
        StepProgress& progress = context;
        progress.stopIterations = false;
        runAll(list(Part::Before), context, times);
        for (progress.corrections = 0; progress.corrections < progress.maxIterations;
             ++progress.corrections) {
            runAll(list(Part::Iteration), context, times);
            if (progress.stopIterations) break;
            times.iterations += 1.0;
        }
        progress.stopIterations = false;
        runAll(list(Part::After), context, times);
        times.total = millisecondsSince(start);
    }

  private:
    using Clock = std::chrono::steady_clock;

    static double millisecondsSince(Clock::time_point start) {
        return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
    }

    // Runs the enabled stages of one list, none after a stage that stopped
    // the iterations (only an iteration's stages do).
    static void runAll(const std::vector<StageEntry<Context>>& entries, Context& context,
                       StageTimes& times) {
        for (const StageEntry<Context>& e : entries) {
            if (e.enabled && !e.enabled(context)) continue;
            const auto start = Clock::now();
            e.run(context);
            const double ms = millisecondsSince(start);
            const StageInfo& info = stageInfo(e.stage);
            times.*info.phase += ms;
            if (info.part) times.*info.part += ms;
            if (static_cast<const StepProgress&>(context).stopIterations) return;
        }
    }

    std::vector<StageEntry<Context>>& list(Part part) { return parts_[std::size_t(part)]; }
    const std::vector<StageEntry<Context>>& list(Part part) const {
        return parts_[std::size_t(part)];
    }

    void insert(Stage anchor, std::ptrdiff_t offset, StageEntry<Context> entry) {
        for (auto& entries : parts_)
            for (auto it = entries.begin(); it != entries.end(); ++it)
                if (it->stage == anchor) {
                    entries.insert(it + offset, std::move(entry));
                    return;
                }
        throw std::logic_error("StepPlan: no stage " + std::string(stageInfo(anchor).name));
    }

    std::array<std::vector<StageEntry<Context>>, 3> parts_;
};

}  // namespace pbf
