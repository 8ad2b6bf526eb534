#include "app/cli.hpp"

#include <cmath>
#include <algorithm>
#include <limits>
#include <thread>

#include "common/error.hpp"
#include "solver/parallel/threads.hpp"

namespace talus::cli {

Arguments parse(int argc, char** argv) {
  Arguments args;
  auto value_of = [&](int& i, const std::string& name) -> std::string {
    const std::string current = argv[i];
    const auto equals = current.find('=');
    if (equals != std::string::npos) return current.substr(equals + 1);
    if (i + 1 >= argc) throw Error("option " + name + " needs a value");
    return argv[++i];
  };
  // A finite number in [low, high) (or (low, high) when low is excluded), from "--name=x" or "--name x".
  auto number_of = [&](int& i, const std::string& name, double low, bool exclude_low, double high,
                       const std::string& expected) {
    const std::string text = value_of(i, name);
    std::size_t used = 0;
    double value = std::numeric_limits<double>::quiet_NaN();
    try {
      value = std::stod(text, &used);
    } catch (...) {
      used = 0;
    }
    const bool above_low = exclude_low ? value > low : value >= low;
    if (used != text.size() || !std::isfinite(value) || !above_low || !(value < high))
      throw Error(name + ": expected " + expected + ", got '" + text + "'");
    return value;
  };
  // An integer from "--name=n" or "--name n" (its text into `text`); -1 when the text is none.
  auto integer_of = [&](int& i, const std::string& name, std::string& text) {
    text = value_of(i, name);
    std::size_t used = 0;
    int value = -1;
    try {
      value = std::stoi(text, &used);
    } catch (...) {
      return -1;
    }
    return used == text.size() ? value : -1;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    const std::string name = word.substr(0, word.find('='));
    if (word == "-h" || word == "--help") args.help = true;
    else if (word == "--quiet" || word == "-q") args.quiet = true;
    else if (name == "--set") args.overrides.push_back(value_of(i, name));
    else if (name == "--out") args.out = value_of(i, name);
    else if (name == "--threads") {
      std::string text;
      args.threads = integer_of(i, name, text);
      if (args.threads < 1) throw Error("--threads: expected a positive integer, got '" + text + "'");
      // Each thread holds a grid buffer of its own: far more threads than cores only costs memory.
      const int cores = static_cast<int>(std::thread::hardware_concurrency());
      if (args.threads > solver::thread_cap())
        throw Error("--threads: got '" + text + "', at most " + std::to_string(solver::thread_cap()) + " (4 x the " +
                    std::to_string(cores) + " hardware threads of this machine, never above " +
                    std::to_string(solver::kMaxThreads) + ")");
    } else if (name == "--ranks") {
      std::string text;
      args.ranks = integer_of(i, name, text);
      if (args.ranks < 1 || args.ranks > kMaxRanks)
        throw Error("--ranks: expected an integer from 1 to " + std::to_string(kMaxRanks) + ", got '" + text + "'");
    } else if (name == "--checkpoint-interval") {
      args.checkpoint_interval = number_of(i, name, 0, false, std::numeric_limits<double>::infinity(),
                                           "a time >= 0 in seconds of simulated time");
    } else if (name == "--tolerance") {
      args.tolerance = number_of(i, name, 0, true, 1, "a number in (0, 1)");
    } else if (name == "--levels") {
      // Any integer here; converge says which it accepts (workflow/converge.hpp).
      const double levels = number_of(i, name, -1e9, false, 1e9, "an integer");
      if (levels != std::floor(levels)) throw Error("--levels: expected an integer, got '" + std::to_string(levels) + "'");
      args.levels = static_cast<int>(levels);
    } else if (name == "--ratio") {
      args.ratio = number_of(i, name, -std::numeric_limits<double>::max(), false,
                             std::numeric_limits<double>::infinity(), "a number > 1");
    } else if (name == "--transfers") {
      args.transfers = value_of(i, name);
    } else if (name == "--realisations") {
      std::string text;
      args.realisations = integer_of(i, name, text);
      if (*args.realisations < 1) throw Error("--realisations: expected a positive integer, got '" + text + "'");
    } else if (name == "--seed") {
      args.seed = value_of(i, name);
    } else if (name == "--jobs") {
      std::string text;
      args.jobs = integer_of(i, name, text);
      if (*args.jobs < 1 || *args.jobs > solver::thread_cap())
        throw Error("--jobs: expected an integer from 1 to " + std::to_string(solver::thread_cap()) + ", got '" + text + "'");
    } else if (word == "--restart") args.restart = true;
    else if (word == "--fos") args.fos = true;
    else if (word.rfind("--", 0) == 0) args.flags.push_back(word);
    else if (args.command.empty()) args.command = word;
    else args.positional.push_back(word);
  }
  return args;
}

}  // namespace talus::cli
