// The backend factory and the parts of the seam every backend shares.
#include "pbf/backend.hpp"

#include <stdexcept>
#include <string>

#include "backend/cpu/cpu_backend.hpp"
#include "backend/mpi/mpi_backend.hpp"
#include "backend/reference/reference_backend.hpp"

namespace pbf {

std::string_view backendName(BackendKind kind) {
    switch (kind) {
        case BackendKind::Cpu:
            return "cpu";
        case BackendKind::Reference:
            return "reference";
        case BackendKind::Mpi:
            return "mpi";
    }
    return "unknown";
}

BackendKind parseBackendKind(std::string_view name) {
    for (BackendKind kind : {BackendKind::Cpu, BackendKind::Reference})
        if (name == backendName(kind)) return kind;
    throw std::invalid_argument("device: must be cpu or reference, got \"" + std::string(name) +
                                "\"");
}

std::unique_ptr<Backend> makeBackend(BackendKind kind, const SimulationParams& params,
                                     const BackendOptions& options) {
    switch (kind) {
        case BackendKind::Cpu:
            return std::make_unique<CpuBackend>(params, options);
        case BackendKind::Reference:
            return makeReferenceBackend(params);
        case BackendKind::Mpi:
            return makeMpiBackend(params, options);
    }
    throw std::invalid_argument("makeBackend: unknown backend kind");
}

StageTimes& StageTimes::operator+=(const StageTimes& o) {
    predict += o.predict;
    neighborSearch += o.neighborSearch;
    solve += o.solve;
    postProcess += o.postProcess;
    total += o.total;
    gridBuild += o.gridBuild;
    reorder += o.reorder;
    neighborLists += o.neighborLists;
    lambda += o.lambda;
    deltaP += o.deltaP;
    bodies += o.bodies;
    exchange += o.exchange;
    iterations += o.iterations;
    return *this;
}

StageTimes StageTimes::operator*(double factor) const {
    StageTimes r;
    r.predict = predict * factor;
    r.neighborSearch = neighborSearch * factor;
    r.solve = solve * factor;
    r.postProcess = postProcess * factor;
    r.total = total * factor;
    r.gridBuild = gridBuild * factor;
    r.reorder = reorder * factor;
    r.neighborLists = neighborLists * factor;
    r.lambda = lambda * factor;
    r.deltaP = deltaP * factor;
    r.bodies = bodies * factor;
    r.exchange = exchange * factor;
    r.iterations = iterations * factor;
    return r;
}

}  // namespace pbf
