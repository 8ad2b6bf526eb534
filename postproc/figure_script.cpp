#include "postproc/figure_script.hpp"

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <filesystem>
#include <sstream>

#include "common/error.hpp"

namespace talus::postproc {
namespace {

std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

// The running script and the signal that asked talus to stop while it ran. The handler passes
// the signal on to the script, which then ends, and talus says so (FiguresInterrupted).
volatile std::sig_atomic_t running_child = 0;
volatile std::sig_atomic_t stop_signal = 0;

extern "C" void forward_stop_signal(int signal) {
  stop_signal = signal;
  if (running_child > 0) kill(running_child, signal);
}

// Holds the forwarding handlers of SIGINT and SIGTERM for its lifetime.
class ForwardSignals {
 public:
  ForwardSignals() {
    running_child = 0;
    stop_signal = 0;
    struct sigaction action {};
    action.sa_handler = forward_stop_signal;
    sigemptyset(&action.sa_mask);
    sigaction(SIGINT, &action, &previous_interrupt_);
    sigaction(SIGTERM, &action, &previous_terminate_);
  }
  ~ForwardSignals() {
    sigaction(SIGINT, &previous_interrupt_, nullptr);
    sigaction(SIGTERM, &previous_terminate_, nullptr);
    running_child = 0;
  }
  ForwardSignals(const ForwardSignals&) = delete;
  ForwardSignals& operator=(const ForwardSignals&) = delete;

 private:
  struct sigaction previous_interrupt_ {};
  struct sigaction previous_terminate_ {};
};

// Runs `words` (words[0] an absolute path) with stdout and stderr into one pipe; returns its
// wait status and fills `output`. The child dies with talus (PR_SET_PDEATHSIG), and SIGINT or
// SIGTERM sent to talus meanwhile is passed on to it.
int run_child(const std::vector<std::string>& words, std::string& output) {
  std::vector<char*> argv;
  for (const auto& word : words) argv.push_back(const_cast<char*>(word.c_str()));
  argv.push_back(nullptr);
  int fds[2];
  if (pipe2(fds, O_CLOEXEC) != 0) throw Error(located(words[0], "", "cannot make a pipe for the figure script"));
  const ForwardSignals forwarding;
  const pid_t pid = fork();
  if (pid < 0) {
    close(fds[0]);
    close(fds[1]);
    throw Error(located(words[0], "", "cannot start the figure script"));
  }
  if (pid == 0) {  // the child: only async-signal-safe calls until exec
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    dup2(fds[1], STDOUT_FILENO);
    dup2(fds[1], STDERR_FILENO);
    execv(argv[0], argv.data());
    static const char kFailed[] = "cannot run the Python interpreter\n";
    const ssize_t written = write(STDERR_FILENO, kFailed, sizeof kFailed - 1);
    _exit(written > 0 ? 127 : 126);
  }
  running_child = pid;
  if (stop_signal) kill(pid, stop_signal);  // asked to stop before running_child was set
  close(fds[1]);
  std::array<char, 4096> buffer;
  for (;;) {
    const ssize_t n = read(fds[0], buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    output.append(buffer.data(), static_cast<std::size_t>(n));
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (stop_signal)
    throw FiguresInterrupted(stop_signal, std::string("interrupted by ") + (stop_signal == SIGINT ? "SIGINT" : "SIGTERM") +
                                              " while " + std::filesystem::path(words[1]).filename().string() +
                                              " ran: the script was stopped with talus; what was written before "
                                              "the figures is kept, the figures may be missing or partial");
  return status;
}

}  // namespace

std::string figure_script(const std::string& name) {
#ifdef TALUS_SOURCE_DIR
  return std::string(TALUS_SOURCE_DIR) + "/postproc/" + name;
#else
  return {};
#endif
}

std::string figures_script() { return figure_script("figures.py"); }

void run_figure_script(const std::string& script, const std::vector<std::string>& arguments, std::ostream& log,
                       const std::string& python) {
  const std::string kept = "; what was written before the figures is kept";
  if (script.empty()) throw Error("figures: no figure script in this build" + kept);
  if (!std::filesystem::exists(script)) throw Error(located(script, "", "figure script not found" + kept));
  std::vector<std::string> words{python, script};
  words.insert(words.end(), arguments.begin(), arguments.end());
  std::string command;
  for (const auto& word : words) command += (command.empty() ? "" : " ") + shell_quoted(word);
  // The script's lines go to the log when it succeeds; a failure is said in one message (its
  // last line, e.g. the exception of a traceback), not as the whole traceback.
  std::string output;
  const int status = run_child(words, output);
  std::vector<std::string> lines;
  std::istringstream stream(output);
  for (std::string text; std::getline(stream, text);) lines.push_back(text + "\n");
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    for (const auto& text : lines) log << "  " << text;
    return;
  }
  std::string last;
  for (auto it = lines.rbegin(); it != lines.rend() && last.empty(); ++it) {
    last = *it;
    while (!last.empty() && std::isspace(static_cast<unsigned char>(last.back()))) last.pop_back();
  }
  throw Error(located(script, "", "figures failed: exited with status " +
                                      std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                                      (last.empty() ? "" : ": " + last.substr(0, 500)) + " (run `" + command +
                                      "` to see its whole output)" + kept));
}

}  // namespace talus::postproc
