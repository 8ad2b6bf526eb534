#include "postproc/figure_script.hpp"

#include <array>
#include <cstdio>
#include <filesystem>
#include <sys/wait.h>

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

bool run_figure_script(const std::string& script, const std::vector<std::string>& arguments, std::ostream& log,
                       const std::string& python) {
  if (script.empty() || !std::filesystem::exists(script)) {
    log << "  figures skipped: "
        << (script.empty() ? std::string("no figure script in this build")
                           : std::filesystem::path(script).filename().string() + " not found at " + script)
        << "\n";
    return false;
  }
  std::string command = shell_quoted(python) + " " + shell_quoted(script);
  for (const auto& argument : arguments) command += " " + shell_quoted(argument);
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (!pipe) {
    log << "  figures failed: cannot start `" << command << "`\n";
    return false;
  }
  std::array<char, 4096> line;
  while (std::fgets(line.data(), line.size(), pipe)) log << "  " << line.data();
  const int status = pclose(pipe);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    log << "  figures failed: `" << command << "` exited with status " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1)
        << "\n";
    return false;
  }
  return true;
}

}  // namespace talus::postproc
