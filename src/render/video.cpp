#include "pbf/render/video.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <vector>

extern char** environ;

namespace pbf::render {

std::optional<std::filesystem::path> findProgram(const std::string& program) {
    const char* path = std::getenv("PATH");
    if (path == nullptr) return std::nullopt;
    std::stringstream directories(path);
    std::string directory;
    while (std::getline(directories, directory, ':')) {
        if (directory.empty()) continue;
        const std::filesystem::path candidate = std::filesystem::path(directory) / program;
        if (::access(candidate.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(candidate))
            return candidate;
    }
    return std::nullopt;
}

VideoResult encodeVideo(const std::filesystem::path& frameDirectory, double fps,
                        const std::filesystem::path& output) {
    VideoResult result;
    const auto ffmpeg = findProgram("ffmpeg");
    if (!ffmpeg) {
        result.programMissing = true;
        result.message =
            "ffmpeg is not installed (Debian package ffmpeg), so no video was made; "
            "the PNG frames are in " +
            frameDirectory.string();
        return result;
    }
    const std::string log = output.string() + ".log";
    const std::string partial = output.string() + ".partial.mp4";
    std::vector<std::string> args{ffmpeg->string(), "-y", "-loglevel", "error", "-framerate",
                                  fmt::format("{}", fps), "-i",
                                  (frameDirectory / "frame_%05d.png").string(),
                                  // H.264 in yuv420p needs even sides; players expect yuv420p.
                                  "-vf", "pad=ceil(iw/2)*2:ceil(ih/2)*2", "-c:v", "libx264",
                                  "-pix_fmt", "yuv420p", "-crf", "20", partial};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
    pid_t pid = 0;
    const int spawnError = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (spawnError != 0) {
        result.message = fmt::format("cannot start {}: {}", argv[0], std::strerror(spawnError));
        return result;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        std::filesystem::remove(partial);
        result.message = fmt::format("ffmpeg failed (exit status {}); see {}",
                                     WIFEXITED(status) ? WEXITSTATUS(status) : -1, log);
        return result;
    }
    // Renamed into place only when complete, like every other output file.
    std::filesystem::rename(partial, output);
    std::filesystem::remove(log);
    result.written = true;
    return result;
}

}  // namespace pbf::render
