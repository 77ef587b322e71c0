#include "pbf/io/process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <sstream>

extern char** environ;

namespace pbf {
namespace {

constexpr std::size_t kMaxOutput = 64 * 1024;

bool isExecutableFile(const std::filesystem::path& path) {
    std::error_code ec;
    return ::access(path.c_str(), X_OK) == 0 && std::filesystem::is_regular_file(path, ec);
}

}  // namespace

std::optional<std::filesystem::path> findProgram(const std::string& program) {
    if (program.find('/') != std::string::npos)
        return isExecutableFile(program) ? std::optional<std::filesystem::path>(program)
                                         : std::nullopt;
    const char* path = std::getenv("PATH");
    if (path == nullptr) return std::nullopt;
    std::stringstream directories(path);
    std::string directory;
    while (std::getline(directories, directory, ':')) {
        if (directory.empty()) continue;
        const std::filesystem::path candidate = std::filesystem::path(directory) / program;
        if (isExecutableFile(candidate)) return candidate;
    }
    return std::nullopt;
}

ProgramResult runProgram(const std::vector<std::string>& argv) {
    ProgramResult result;
    if (argv.empty()) {
        result.output = "no program given";
        return result;
    }
    int pipeEnds[2];
    if (::pipe2(pipeEnds, O_CLOEXEC) != 0) {
        result.output = std::string("cannot create a pipe: ") + std::strerror(errno);
        return result;
    }
    std::vector<std::string> args = argv;
    std::vector<char*> pointers;
    for (std::string& a : args) pointers.push_back(a.data());
    pointers.push_back(nullptr);

    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
    // dup2 clears O_CLOEXEC on the copies, so the child keeps only these two.
    posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDERR_FILENO);
    pid_t pid = 0;
    const int spawnError =
        posix_spawn(&pid, pointers[0], &actions, nullptr, pointers.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    ::close(pipeEnds[1]);
    if (spawnError != 0) {
        ::close(pipeEnds[0]);
        result.output = "cannot start " + argv[0] + ": " + std::strerror(spawnError);
        return result;
    }
    result.started = true;
    char buffer[4096];
    for (;;) {
        const ::ssize_t n = ::read(pipeEnds[0], buffer, sizeof buffer);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) break;
        result.output.append(buffer, std::size_t(n));
        // Keep the end: that is where programs say what went wrong.
        if (result.output.size() > 2 * kMaxOutput)
            result.output.erase(0, result.output.size() - kMaxOutput);
    }
    ::close(pipeEnds[0]);
    if (result.output.size() > kMaxOutput)
        result.output.erase(0, result.output.size() - kMaxOutput);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    result.exitStatus = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return result;
}

}  // namespace pbf
