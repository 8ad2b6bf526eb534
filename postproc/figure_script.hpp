// The figure scripts of postproc (figures.py for `talus post`, fos_figure.py for `talus fos`):
// where this build finds them, and the one runner of them both.
#pragma once
#include <ostream>
#include <string>
#include <vector>

namespace talus::postproc {

// TALUS_SOURCE_DIR/postproc/NAME when the library was compiled with that definition, else empty.
std::string figure_script(const std::string& name);

// The figures script this build uses by default: figure_script("figures.py").
std::string figures_script();

// Runs `python script arguments...`. When it exits with status 0, the script's own lines go to
// `log`, indented; otherwise, or when the script is missing (an empty path included), throws
// talus::Error naming the script, its status and its last line (of a traceback, the exception).
void run_figure_script(const std::string& script, const std::vector<std::string>& arguments, std::ostream& log,
                       const std::string& python = "/usr/bin/python3");

}  // namespace talus::postproc
