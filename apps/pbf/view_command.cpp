// `pbf view SCENE`: the interactive viewer (needs a display; see `pbf render`).
#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "commands.hpp"
#include "console.hpp"
#include "device_option.hpp"
#include "pbf/core/threading.hpp"
#include "pbf/io/scene.hpp"
#include "pbf/render/viewer.hpp"

namespace pbf::cli {
namespace {

struct ViewArguments {
    std::string scene;
    int width = 1280;
    int height = 720;
    std::string style = "spheres";
    std::string color = "speed";
    std::string screenshot;
    int frames = 0;
    bool paused = false;
    int threads = 0;
    std::vector<std::string> overrides;
    std::string device = "cpu";
};

int runView(const ViewArguments& args) {
    if (const std::string problem = render::validateResolution(args.width, args.height);
        !problem.empty())
        throw std::invalid_argument(problem);
    std::vector<SceneOverride> overrides;
    for (const std::string& o : args.overrides) overrides.push_back(parseOverride(o));
    const Scene scene = loadScene(args.scene, overrides);
    const BackendKind device = selectDevice(args.device);
    // One core stays free for the window: an oversubscribed OpenMP team
    // (simulation threads + the UI thread + llvmpipe's) waits at every barrier.
    setThreadCount(args.threads > 0 ? args.threads : std::max(1, hardwareThreadCount() - 1));

    render::ViewerOptions options;
    options.width = args.width;
    options.height = args.height;
    options.settings.style = render::parseStyle(args.style);
    options.settings.color = render::parseColorMode(args.color);
    render::setDefaultRange(options.settings, scene.simulation);
    options.paused = args.paused;
    options.screenshot = args.screenshot;
    options.frames = args.frames;
    options.device = device;
    if (!args.screenshot.empty() && args.frames <= 0) options.frames = 1;

    const render::ViewerSummary s = render::runViewer(scene, options);
    fmt::print(
        "pbf view: {} frames simulated ({:.1f} ms each), {} frames drawn ({:.1f} ms each){}\n",
        s.framesSimulated, s.averageStepMs, s.framesDrawn, s.averageRenderMs,
        args.screenshot.empty() ? "" : ", screenshot " + args.screenshot);
    if (!s.error.empty()) {
        printError(s.error);
        return 4;
    }
    return 0;
}

}  // namespace

std::function<int()> addViewCommand(CLI::App& app) {
    auto args = std::make_shared<ViewArguments>();
    CLI::App* cmd = app.add_subcommand(
        "view", "Simulate a scene live in a window (needs a display; see pbf render)");
    cmd->add_option("scene", args->scene, "Scene file (JSON, see docs/scenes.md)")->required();
    cmd->add_option("--width", args->width, "Window width in pixels")->capture_default_str();
    cmd->add_option("--height", args->height, "Window height in pixels")->capture_default_str();
    cmd->add_option("--style", args->style, "spheres or liquid (switchable in the panel)")
        ->capture_default_str();
    cmd->add_option("--color", args->color, "speed, density or flat (switchable in the panel)")
        ->capture_default_str();
    cmd->add_flag("--paused", args->paused, "Start paused");
    cmd->add_option("--screenshot", args->screenshot,
                    "Simulate --frames frames, save the window as this PNG and quit");
    cmd->add_option("--frames", args->frames,
                    "Frames to simulate before the screenshot (default 1)")
        ->check(CLI::Range(1, 1000000));
    cmd->add_option("-t,--threads", args->threads,
                    "Simulation threads (default: all cores but one)")
        ->check(CLI::Range(1, 1024));
    cmd->add_option("-s,--set", args->overrides,
                    "Override a scene field, e.g. --set solver.iterations=8")
        ->take_all();
    addDeviceOption(cmd, args->device);
    return [args] { return runView(*args); };
}

}  // namespace pbf::cli
