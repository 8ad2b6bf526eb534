#include "app/cli.hpp"

#include <cmath>

#include "common/error.hpp"

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
  for (int i = 1; i < argc; ++i) {
    const std::string word = argv[i];
    const std::string name = word.substr(0, word.find('='));
    if (word == "-h" || word == "--help") args.help = true;
    else if (word == "--quiet" || word == "-q") args.quiet = true;
    else if (name == "--set") args.overrides.push_back(value_of(i, name));
    else if (name == "--out") args.out = value_of(i, name);
    else if (name == "--threads") {
      const std::string text = value_of(i, name);
      try {
        args.threads = std::stoi(text);
      } catch (...) {
        args.threads = -1;
      }
      if (args.threads < 1) throw Error("--threads: expected a positive integer, got '" + text + "'");
    } else if (name == "--checkpoint-interval") {
      const std::string text = value_of(i, name);
      std::size_t used = 0;
      double value = -1;
      try {
        value = std::stod(text, &used);
      } catch (...) {
        used = 0;
      }
      if (used != text.size() || !std::isfinite(value) || value < 0)
        throw Error("--checkpoint-interval: expected a time >= 0 in seconds of simulated time, got '" + text + "'");
      args.checkpoint_interval = value;
    } else if (word == "--restart") args.restart = true;
    else if (word.rfind("--", 0) == 0) args.flags.push_back(word);
    else if (args.command.empty()) args.command = word;
    else args.positional.push_back(word);
  }
  return args;
}

}  // namespace talus::cli
