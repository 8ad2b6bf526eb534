#include "postproc/figure_script.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <sys/wait.h>

#include <cctype>

#include "common/error.hpp"

namespace talus::postproc {
namespace {

std::string shell_quoted(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
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
  std::string command = shell_quoted(python) + " " + shell_quoted(script);
  for (const auto& argument : arguments) command += " " + shell_quoted(argument);
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) throw Error(located(script, "", "cannot start `" + command + "`" + kept));
  // The script's lines go to the log when it succeeds; a failure is said in one message (its
  // last line, e.g. the exception of a traceback), not as the whole traceback.
  std::vector<std::string> lines;
  std::array<char, 4096> line;
  while (std::fgets(line.data(), line.size(), pipe)) lines.emplace_back(line.data());
  const int status = pclose(pipe);
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
