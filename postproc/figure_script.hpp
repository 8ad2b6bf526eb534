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

// Runs `python script arguments...`; the script's own lines (what it wrote, or its traceback)
// go to `log`, indented. Returns true when it exited with status 0; otherwise, or when the
// script is missing (an empty path included), the log says why and it returns false.
bool run_figure_script(const std::string& script, const std::vector<std::string>& arguments, std::ostream& log,
                       const std::string& python = "/usr/bin/python3");

}  // namespace talus::postproc
