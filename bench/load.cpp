// A solve on a busy machine: the time loop of `talus solve` alone, then with one CPU-bound
// competitor per core (child processes of this benchmark spinning on arithmetic), and their
// ratio. The competitors are started and stopped around each loaded run; they die with this
// program (PR_SET_PDEATHSIG), on Ctrl-C and on any error, so none is left behind.
//
//   talus_bench_load                                      the default slope, auto threads and 2
//   talus_bench_load --talus OLD --talus NEW --repeats 5  two builds, alternately
//   talus_bench_load --set mesh.size=0.3 --threads 2      the scene and the solve's options
//   talus_bench_load --late 1 --set run.max_steps=6000    the load starts 1 s after talus does
//
// Each repeat runs every (binary, thread setting) quiet and then loaded, one after the other,
// so that a change of the machine's own load hits all of them alike; medians are reported.
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "solver/parallel/threads.hpp"

namespace {

std::vector<pid_t> competitors;

void stop_competitors() {
  for (pid_t pid : competitors) kill(pid, SIGKILL);
  for (pid_t pid : competitors) waitpid(pid, nullptr, 0);
  competitors.clear();
}

void on_signal(int signal) {
  for (pid_t pid : competitors) kill(pid, SIGKILL);
  std::_Exit(128 + signal);
}

// One busy child per core: floating-point work with no memory traffic and no system calls.
void start_competitors(int count) {
  const pid_t parent = getpid();
  for (int i = 0; i < count; ++i) {
    const pid_t pid = fork();
    if (pid < 0) {
      stop_competitors();
      throw std::runtime_error("fork failed");
    }
    if (pid == 0) {
      prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (getppid() != parent) std::_Exit(0);  // the parent died before prctl
      volatile double x = 1.0;
      for (;;) x = x * 1.0000001 + 1e-9;
    }
    competitors.push_back(pid);
  }
  usleep(200000);  // let the scheduler see them
}

struct Stopper {  // stops the competitors on every way out of a scope, exceptions included
  ~Stopper() { stop_competitors(); }
};

// Runs `command` (through the shell), returns its standard output.
std::string output_of(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) throw std::runtime_error("cannot run " + command);
  std::string out;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) out += buffer;
  if (pclose(pipe) != 0) throw std::runtime_error("failed: " + command + "\n" + out);
  return out;
}

struct Run {
  double loop_seconds = 0, wall_seconds = 0;
  std::string threads;  // as the summary line says
};

Run solve(const std::string& talus, const std::string& model, const std::string& out, const std::string& threads) {
  const std::string command = talus + " solve " + model + " --out " + out +
                              (threads == "auto" ? "" : " --threads " + threads) + " 2>&1";
  const auto start = std::chrono::steady_clock::now();
  const std::string text = output_of(command);
  Run run;
  run.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const auto at = text.find("time loop ");
  if (at == std::string::npos || std::sscanf(text.c_str() + at, "time loop %lf s", &run.loop_seconds) != 1)
    throw std::runtime_error("no 'time loop' in the output of " + command + ":\n" + text);
  const auto on = text.find(" on ", at);
  if (on != std::string::npos) {  // "2 threads" or "1 thread (auto: 6,248 particles, 2 cores)"
    auto end = text.find(", ", on);
    const auto open = text.find(" (", on);
    if (open < end) end = text.find(')', open) + 1;
    run.threads = text.substr(on + 4, end - on - 4);
  }
  return run;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> binaries, sets, thread_settings;
  std::string scene = std::string(TALUS_SOURCE_DIR) + "/geometries/slope.toml", csv;
  int repeats = 3, count = talus::solver::available_cores();
  double late = 0;  // seconds after talus starts that the competitors start (0: before it)
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&] {
      if (i + 1 >= argc) throw std::runtime_error(arg + ": expected a value");
      return std::string(argv[++i]);
    };
    try {
      if (arg == "--talus") binaries.push_back(value());
      else if (arg == "--scene") scene = value();
      else if (arg == "--set") sets.push_back(value());
      else if (arg == "--threads") thread_settings.push_back(value());
      else if (arg == "--repeats") repeats = std::max(1, std::stoi(value()));
      else if (arg == "--competitors") count = std::max(1, std::stoi(value()));
      else if (arg == "--csv") csv = value();
      else if (arg == "--late") {
        late = std::stod(value());
        if (!(late >= 0 && late < 3600)) throw std::runtime_error("--late: expected seconds in [0, 3600)");
      }
      else {
        std::printf(
            "usage: %s [--talus BINARY]... [--scene SCENE.toml] [--set KEY=VALUE]... [--threads N|auto]...\n"
            "          [--repeats N] [--competitors N] [--late SECONDS] [--csv FILE]\n"
            "defaults: this build's talus; geometries/slope.toml with mesh.size=0.25, run.max_steps=1500;\n"
            "--threads auto and 2; 3 repeats; one competitor per core (%d here); the competitors start\n"
            "before talus, or --late SECONDS after it (a load that starts during the solve: give a\n"
            "scene whose quiet time loop is longer, e.g. --set run.max_steps=6000)\n",
            argv[0], count);
        return arg == "--help" || arg == "-h" ? 0 : 1;
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "talus_bench_load: %s\n", e.what());
      return 1;
    }
  }
  if (binaries.empty()) binaries.push_back(TALUS_BINARY);
  if (sets.empty()) sets = {"mesh.size=0.25", "run.max_steps=1500"};
  if (thread_settings.empty()) thread_settings = {"auto", "2"};
  signal(SIGINT, on_signal);
  signal(SIGTERM, on_signal);
  signal(SIGHUP, on_signal);

  const auto folder = std::filesystem::temp_directory_path() / ("talus-bench-load-" + std::to_string(getpid()));
  try {
    Stopper stopper;
    std::filesystem::create_directories(folder);
    std::string mesh = binaries.back() + " mesh " + scene + " --quiet --out " + folder.string();
    for (const auto& s : sets) mesh += " --set " + s;
    output_of(mesh + " 2>&1");
    const std::string model = (folder / "model.h5").string();

    struct Series {
      std::string binary, threads, chosen;
      std::vector<double> quiet, loaded, ratio;
    };
    std::vector<Series> series;
    for (const auto& b : binaries)
      for (const auto& t : thread_settings) series.push_back({b, t, "", {}, {}, {}});
    for (int r = 0; r < repeats; ++r)
      for (Series& s : series) {
        const Run quiet = solve(s.binary, model, folder.string(), s.threads);
        Run loaded;
        if (late > 0) {
          // The competitors start `late` seconds into the solve, from a second thread, which
          // also stops them: a child's PR_SET_PDEATHSIG fires when the thread that forked it ends.
          std::exception_ptr failed;
          std::mutex mutex;
          std::condition_variable changed;
          bool done = false;
          std::thread starter([&] {
            std::unique_lock<std::mutex> lock(mutex);
            try {
              if (!changed.wait_for(lock, std::chrono::duration<double>(late), [&] { return done; }))
                start_competitors(count);
            } catch (...) {
              failed = std::current_exception();
            }
            changed.wait(lock, [&] { return done; });
            stop_competitors();
          });
          auto finish = [&] {
            {
              std::lock_guard<std::mutex> lock(mutex);
              done = true;
            }
            changed.notify_all();
            starter.join();
          };
          try {
            loaded = solve(s.binary, model, folder.string(), s.threads);
          } catch (...) {
            finish();
            throw;
          }
          finish();
          if (failed) std::rethrow_exception(failed);
        } else {
          start_competitors(count);
          loaded = solve(s.binary, model, folder.string(), s.threads);
        }
        stop_competitors();
        s.chosen = quiet.threads;
        s.quiet.push_back(quiet.loop_seconds);
        s.loaded.push_back(loaded.loop_seconds);
        s.ratio.push_back(loaded.loop_seconds / quiet.loop_seconds);
        std::fprintf(stderr, "  %s --threads %s: quiet %.2f s, loaded %.2f s (x%.2f)\n", s.binary.c_str(),
                     s.threads.c_str(), quiet.loop_seconds, loaded.loop_seconds, s.ratio.back());
      }
    std::ifstream load("/proc/loadavg");
    std::string loadavg;
    std::getline(load, loadavg);
    std::printf("scene %s", scene.c_str());
    for (const auto& s : sets) std::printf(" --set %s", s.c_str());
    std::printf("; %d competitors", count);
    if (late > 0) std::printf(", started %.1f s after talus", late);
    std::printf("; load average at the end: %s\n\n", loadavg.c_str());
    std::printf("| binary | --threads | ran on | quiet loop (s, median of %d) | loaded loop (s) | loaded / quiet (median) |\n",
                repeats);
    std::printf("|---|---|---|---:|---:|---:|\n");
    std::ofstream out;
    if (!csv.empty()) {
      out.open(csv);
      out << "binary,threads,ran_on,repeats,quiet_seconds,loaded_seconds,ratio\n";
    }
    for (const Series& s : series) {
      std::printf("| %s | %s | %s | %.2f | %.2f | %.2f |\n", s.binary.c_str(), s.threads.c_str(), s.chosen.c_str(),
                  median(s.quiet), median(s.loaded), median(s.ratio));
      if (out)
        out << s.binary << "," << s.threads << ",\"" << s.chosen << "\"," << repeats << "," << median(s.quiet) << ","
            << median(s.loaded) << "," << median(s.ratio) << "\n";
    }
  } catch (const std::exception& e) {
    std::filesystem::remove_all(folder);
    std::fprintf(stderr, "talus_bench_load: %s\n", e.what());
    return 1;
  }
  std::filesystem::remove_all(folder);
  return 0;
}
