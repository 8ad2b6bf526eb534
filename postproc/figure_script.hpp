// The figure scripts of postproc (figures.py for `talus post`, fos_figure.py for `talus fos`):
// where this build finds them, and the one runner of them both.
#pragma once
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace talus::postproc {

// TALUS_SOURCE_DIR/postproc/NAME when the library was compiled with that definition, else empty.
std::string figure_script(const std::string& name);

// The figures script this build uses by default: figure_script("figures.py").
std::string figures_script();

// SIGINT or SIGTERM reached talus while a figure script ran: the script was stopped too.
struct FiguresInterrupted : std::runtime_error {
  FiguresInterrupted(int signal_number, const std::string& message)
      : std::runtime_error(message), signal(signal_number) {}
  int signal;
};

// Runs `python script arguments...`. When it exits with status 0, the script's own lines go to
// `log`, indented; otherwise, or when the script is missing (an empty path included), throws
// talus::Error naming the script, its status and its last line (of a traceback, the exception).
// The script runs without a shell and ends with talus: SIGINT or SIGTERM sent to talus while it
// runs is passed on to it, then FiguresInterrupted is thrown.
void run_figure_script(const std::string& script, const std::vector<std::string>& arguments, std::ostream& log,
                       const std::string& python = "/usr/bin/python3");

}  // namespace talus::postproc
