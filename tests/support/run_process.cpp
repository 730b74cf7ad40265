#include "support/run_process.hpp"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <stdexcept>

namespace dfm::test {

namespace {

void drain(int fd, std::string& into) {
    char buf[4096];
    for (ssize_t n; (n = read(fd, buf, sizeof buf)) > 0;)
        into.append(buf, static_cast<std::size_t>(n));
}

}  // namespace

ProcessResult run_process(const std::string& program, const std::vector<std::string>& args) {
    // stderr goes to a temporary file so two pipes can never deadlock.
    char err_path[] = "/tmp/dualform-test-err-XXXXXX";
    const int err_fd = mkstemp(err_path);
    int out_pipe[2];
    if (err_fd < 0 || pipe(out_pipe) != 0)
        throw std::runtime_error("cannot set up a child process");
    const pid_t pid = fork();
    if (pid < 0) throw std::runtime_error("fork failed");
    if (pid == 0) {
        dup2(out_pipe[1], 1);
        dup2(err_fd, 2);
        close(out_pipe[0]);
        std::vector<char*> argv;
        argv.push_back(const_cast<char*>(program.c_str()));
        for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
        argv.push_back(nullptr);
        execv(program.c_str(), argv.data());
        _exit(127);
    }
    close(out_pipe[1]);
    ProcessResult r;
    drain(out_pipe[0], r.out);
    close(out_pipe[0]);
    int status = 0;
    waitpid(pid, &status, 0);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    lseek(err_fd, 0, SEEK_SET);
    drain(err_fd, r.err);
    close(err_fd);
    unlink(err_path);
    return r;
}

}  // namespace dfm::test
