// The one runner of the figure scripts (postproc/figure_script.hpp), used by `talus post` and
// `talus fos`: arguments with quotes and spaces arrive intact, the script's lines go to the log,
// and a failing or missing script is one talus::Error.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "common/error.hpp"
#include "postproc/figure_script.hpp"
#include "support/test_support.hpp"

namespace talus::postproc {
namespace {

TEST(FigureScript, TheScriptsOfThisBuildAreInTheSourceTree) {
  EXPECT_EQ(figures_script(), figure_script("figures.py"));
  EXPECT_TRUE(std::filesystem::exists(figure_script("figures.py")));
  EXPECT_TRUE(std::filesystem::exists(figure_script("fos_figure.py")));
}

TEST(FigureScript, RunsTheScriptWithItsArgumentsAndLogsItsLines) {
  testing::ScratchDir dir("figure-script");
  const std::string script = dir.file("echo.py");
  std::ofstream(script) << "import sys\nprint('|'.join(sys.argv[1:]))\nprint('to stderr', file=sys.stderr)\n";
  std::ostringstream log;
  EXPECT_NO_THROW(run_figure_script(script, {"--out", "a folder/with 'quotes'"}, log)) << log.str();
  EXPECT_NE(log.str().find("  --out|a folder/with 'quotes'\n"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("  to stderr\n"), std::string::npos) << log.str();
}

// Said in one message (thrown, so that `talus post -q` says it too): the script, its status and
// its last line, not the whole traceback.
std::string failure_of(const std::string& script, std::ostringstream& log) {
  try {
    run_figure_script(script, {}, log);
  } catch (const Error& error) {
    return error.what();
  }
  return "(no error)";
}

TEST(FigureScript, AFailingOrMissingScriptIsOneMessage) {
  testing::ScratchDir dir("figure-script-fails");
  const std::string script = dir.file("fails.py");
  std::ofstream(script) << "print('drawing')\ndef draw():\n    raise RuntimeError('no matplotlib here')\ndraw()\n";
  std::ostringstream log;
  const std::string failed = failure_of(script, log);
  EXPECT_NE(failed.find(script + ": figures failed: exited with status 1: RuntimeError: no matplotlib here"),
            std::string::npos)
      << failed;
  EXPECT_NE(failed.find("what was written before the figures is kept"), std::string::npos) << failed;
  EXPECT_EQ(failed.find("Traceback"), std::string::npos) << failed;
  EXPECT_EQ(log.str().find("Traceback"), std::string::npos) << log.str();

  std::ostringstream missing;
  EXPECT_NE(failure_of(dir.file("absent.py"), missing).find("absent.py: figure script not found"), std::string::npos);
  std::ostringstream empty;
  EXPECT_NE(failure_of("", empty).find("no figure script in this build"), std::string::npos);
}

}  // namespace
}  // namespace talus::postproc
