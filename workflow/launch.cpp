#include "workflow/launch.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <stdexcept>
#include <vector>

#include "common/error.hpp"
#include "solver/parallel/parallel.hpp"
#include "workflow/folder_lock.hpp"
#include "workflow/ranks_link.hpp"

namespace fs = std::filesystem;

namespace talus::workflow {
namespace {

// The signal (SIGINT or SIGTERM) this process got while it waited for mpirun, and how many.
volatile std::sig_atomic_t parent_signal = 0;
volatile std::sig_atomic_t parent_signals = 0;

extern "C" void on_parent_signal(int signal) {
  parent_signal = signal;
  parent_signals = parent_signals + 1;
}

// `name` found in a folder of PATH, or empty.
std::string on_path(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::stringstream folders(path ? path : "/usr/bin:/bin");
  std::string folder;
  while (std::getline(folders, folder, ':')) {
    const fs::path candidate = fs::path(folder.empty() ? "." : folder) / name;
    if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

// "SIGKILL" for 9, "signal 64" for a number without a name.
std::string signal_name(int signal) {
  const char* abbreviation = sigabbrev_np(signal);
  return abbreviation ? std::string("SIG") + abbreviation : "signal " + std::to_string(signal);
}

std::string number(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

}  // namespace

bool launched_by_ranks_parent() {
  const char* value = std::getenv(kRanksChildVariable);
  return value && std::string(value) == "1";
}

void solve_on_ranks(const std::string& model_path, const std::string& folder, const StageOptions& options,
                    std::ostream& log) {
  RanksCommand command;
  command.ranks = options.ranks;
  command.arguments = {"solve", model_path, "--out", folder};
  if (options.threads > 0) command.arguments.insert(command.arguments.end(), {"--threads", std::to_string(options.threads)});
  if (options.quiet) command.arguments.push_back("--quiet");
  if (options.checkpoint_interval > 0)
    command.arguments.insert(command.arguments.end(), {"--checkpoint-interval", number(options.checkpoint_interval)});
  if (options.restart) command.arguments.push_back("--restart");
  command.folder = folder;
  command.quiet = options.quiet;
  command.doing = "solving";
  command.kept = (fs::path(folder) / "results.h5").string() +
                 " keeps the frames written before, marked incomplete; restart from a checkpoint with --restart if "
                 "one was written";
  run_on_ranks(command, log);
}

void take_lock_from_ranks_driver(const std::string& folder) {
  signal(SIGPIPE, SIG_IGN);  // a terminal gone with the parent fails a write, and kills no rank
  const std::string why = join_ranks_driver();
  const int first = solver::mpi::first_rank_with(!why.empty());
  if (first >= 0) {
    std::string reason = why;
    solver::mpi::broadcast(reason, first);
    throw SharedError(located(folder, "", "rank " + std::to_string(first) + " " + reason + "; nothing was written"));
  }
}

void run_on_ranks(const RanksCommand& command, std::ostream& log) {
  const std::string ranks = std::to_string(command.ranks);
  const std::string& folder = command.folder;
  if (!solver::mpi::built_with_mpi())
    throw Error("--ranks " + ranks +
                ": this talus was built without MPI (it needs the Debian packages libopenmpi-dev, openmpi-bin "
                "and libmetis-dev, which ./talus installs; then rebuild)");
  const std::string mpirun = on_path("mpirun");
  if (mpirun.empty())
    throw Error("--ranks " + ranks + ": mpirun is not on PATH (Debian package openmpi-bin; ./talus installs it)");
  std::error_code error;
  const std::string self = fs::read_symlink("/proc/self/exe", error).string();
  if (error) throw Error("--ranks: cannot find this program's own file (/proc/self/exe): " + error.message());

  std::vector<std::string> words{mpirun, "-n", ranks, "--oversubscribe", "--bind-to", "none", "--quiet"};
  if (geteuid() == 0) words.push_back("--allow-run-as-root");  // OpenMPI refuses root without it
  words.push_back(self);
  words.insert(words.end(), command.arguments.begin(), command.arguments.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);

  // The ranks take the folder's lock from this process (ranks_link.hpp): mpirun closes the
  // descriptors it would inherit.
  const int lock_fd = FolderLock::held_descriptor(folder);
  if (lock_fd < 0) throw std::logic_error("--ranks: the folder's lock is not held by this process");
  RanksListener listener(lock_fd);
  const pid_t driver = getpid();

  if (!command.quiet) log << command.doing << " on " << ranks << " MPI ranks (mpirun)" << std::endl;
  log.flush();
  // Ctrl-C and SIGTERM are caught from here on: until mpirun has gone, this process forwards them.
  parent_signal = 0;
  parent_signals = 0;
  struct sigaction action {}, previous_interrupt {}, previous_terminate {};
  action.sa_handler = on_parent_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // waitpid returns with EINTR: the signal is forwarded at once
  sigaction(SIGINT, &action, &previous_interrupt);
  sigaction(SIGTERM, &action, &previous_terminate);
  auto restore = [&] {
    sigaction(SIGINT, &previous_interrupt, nullptr);
    sigaction(SIGTERM, &previous_terminate, nullptr);
  };

  const pid_t child = fork();
  if (child < 0) {
    restore();
    throw Error(std::string("--ranks: cannot start mpirun: ") + std::strerror(errno));
  }
  if (child == 0) {
    // mpirun in a process group of its own, reading nothing: a Ctrl-C at the terminal reaches
    // this process alone, which forwards it as the ranks understand it (mpirun's own handling of
    // SIGINT kills the ranks a second later, too soon for a checkpoint).
    setpgid(0, 0);
    // When this process dies (even by kill -9), mpirun gets SIGUSR2, which it forwards to the
    // ranks as a SIGTERM would be (they stop after the step with a checkpoint); the ranks also
    // watch their link to this process. If it died before prctl, mpirun is not started.
    prctl(PR_SET_PDEATHSIG, SIGUSR2);
    if (getppid() != driver) _exit(128 + SIGUSR2);
    const int null = open("/dev/null", O_RDONLY);
    if (null >= 0) dup2(null, STDIN_FILENO);
    setenv(kRanksChildVariable, "1", 1);
    setenv(kRanksSocketVariable, listener.name().c_str(), 1);
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    execv(mpirun.c_str(), argv.data());
    const std::string message = "talus: error: --ranks: cannot run " + mpirun + ": " + std::strerror(errno) + "\n";
    [[maybe_unused]] const ssize_t written = write(STDERR_FILENO, message.data(), message.size());
    _exit(127);
  }
  int forwarded = 0;
  int status = 0;
  for (;;) {
    if (parent_signals > forwarded) {
      // The first signal asks the ranks to stop after the step; a second one stops mpirun.
      const int what = forwarded == 0 ? (parent_signal == SIGINT ? SIGUSR1 : SIGUSR2) : SIGTERM;
      kill(child, what);
      forwarded = parent_signals;
    }
    const pid_t done = waitpid(child, &status, WNOHANG);
    if (done == child) break;
    if (done < 0 && errno != EINTR) {
      restore();
      throw Error(std::string("--ranks: lost mpirun: ") + std::strerror(errno));
    }
    listener.serve(50);  // a signal cuts it short
  }
  restore();
  listener.serve(0);  // what the ranks said last
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  // Stopped by a signal here: the ranks exit 128 + its number; mpirun may report another status.
  if (parent_signal != 0 && code != 0) code = 128 + parent_signal;
  const int killed = parent_signal == 0 ? listener.killed_rank() : -1;
  if (killed >= 0) {
    // A rank ended without a word (mpirun, with --quiet, says nothing): killed by a signal,
    // which mpirun's status carries as 128 + its number.
    std::ostringstream message;
    message << "--ranks " << ranks << ": rank " << killed << " (pid " << listener.pid_of(killed) << ") ";
    if (code > 128 && code < 128 + 65) message << "was killed by " << signal_name(code - 128);
    else message << "ended without a word (mpirun's status " << code << ")";
    message << "; mpirun stopped the other ranks. " << command.kept;
    throw RanksFailed{code, message.str()};
  }
  throw RanksFailed{code, ""};
}

}  // namespace talus::workflow
