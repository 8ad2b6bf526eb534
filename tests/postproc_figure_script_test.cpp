// The one runner of the figure scripts (postproc/figure_script.hpp), used by `talus post` and
// `talus fos`: arguments with quotes and spaces arrive intact, the script's lines go to the log,
// and a failing or missing script is said in the log and returns false.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

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
  EXPECT_TRUE(run_figure_script(script, {"--out", "a folder/with 'quotes'"}, log)) << log.str();
  EXPECT_NE(log.str().find("  --out|a folder/with 'quotes'\n"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("  to stderr\n"), std::string::npos) << log.str();
}

TEST(FigureScript, AFailingOrMissingScriptIsSaidAndReturnsFalse) {
  testing::ScratchDir dir("figure-script-fails");
  const std::string script = dir.file("fails.py");
  std::ofstream(script) << "raise SystemExit('no matplotlib here')\n";
  std::ostringstream log;
  EXPECT_FALSE(run_figure_script(script, {}, log));
  EXPECT_NE(log.str().find("  no matplotlib here\n"), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("figures failed: "), std::string::npos) << log.str();
  EXPECT_NE(log.str().find("exited with status 1"), std::string::npos) << log.str();

  std::ostringstream missing;
  EXPECT_FALSE(run_figure_script(dir.file("absent.py"), {}, missing));
  EXPECT_NE(missing.str().find("figures skipped: absent.py not found at "), std::string::npos) << missing.str();
  std::ostringstream empty;
  EXPECT_FALSE(run_figure_script("", {}, empty));
  EXPECT_NE(empty.str().find("figures skipped"), std::string::npos) << empty.str();
}

}  // namespace
}  // namespace talus::postproc
