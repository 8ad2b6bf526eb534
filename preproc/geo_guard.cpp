#include "preproc/geo_guard.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#include "common/error.hpp"

namespace talus::preproc {
namespace {

namespace fs = std::filesystem;

constexpr std::size_t kMaxIncludeDepth = 16;
const char* const kSubset = "a Talus .geo may only build geometry, name physical groups and set Mesh.* and "
                            "Geometry.* options: see docs/scenes.md";

// Statements gmsh runs while it parses, and why each is refused.
const std::map<std::string, std::string>& refused_words() {
  static const std::map<std::string, std::string> words = {
      {"System", "it runs a shell command"},
      {"SystemCall", "it runs a shell command"},
      {"NonBlockingSystemCall", "it runs a shell command"},
      {"OnelabRun", "it runs a program"},
      {"OnelabAction", "it drives external programs"},
      {"ExternalProcess", "the field runs a program"},
      {"Save", "it writes a file"},
      {"Print", "it writes a file"},
      {"CreateDir", "it creates a folder"},
      {"CreateFolder", "it creates a folder"},
      {"DeleteFile", "it deletes a file"},
      {"RenameFile", "it renames a file"},
      {"Merge", "it reads another file"},
      {"MergeWithBoundingBox", "it reads another file"},
      {"ShapeFromFile", "it reads another file"},
      {"ListFromFile", "it reads another file"},
      {"FileExists", "it probes the file system"},
      {"GetEnv", "it reads the environment, so the same .geo would mesh differently elsewhere"},
      {"Exit", "it ends the process"},
      {"Abort", "it ends the process"},
      {"Sleep", "it pauses the meshing"},
      {"Draw", "it drives the graphical interface"},
      {"SetChanged", "it drives the graphical interface"},
      {"Plugin", "it runs gmsh plugins, some of which write files"},
      {"View", "post-processing views can write files"},
      {"Combine", "post-processing views can write files"},
  };
  return words;
}

// Option categories other than Mesh and Geometry (General.* holds file names and
// SaveOptions, Solver.* the programs gmsh may start).
bool refused_option_category(const std::string& word) {
  return word == "General" || word == "Solver" || word == "PostProcessing" || word == "Print" || word == "View";
}

struct Token {
  enum Kind { kWord, kString, kNumber, kPunct } kind;
  std::string text;
  int line;
};

bool word_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool word_char(char c) { return word_start(c) || std::isdigit(static_cast<unsigned char>(c)); }

// gmsh's lexical rules: // and /* */ comments, strings in "..." or '...' (no escapes; they may
// span lines), words [A-Za-z_][A-Za-z_0-9]*. Unterminated comments and strings end the text,
// as in gmsh.
std::vector<Token> tokens_of(const std::string& text) {
  std::vector<Token> tokens;
  int line = 1;
  std::size_t i = 0;
  const std::size_t n = text.size();
  auto advance_to = [&](std::size_t end) {
    for (; i < end && i < n; ++i)
      if (text[i] == '\n') ++line;
  };
  while (i < n) {
    const char c = text[i];
    if (c == '/' && i + 1 < n && text[i + 1] == '/') {
      const std::size_t end = text.find('\n', i);
      advance_to(end == std::string::npos ? n : end);
    } else if (c == '/' && i + 1 < n && text[i + 1] == '*') {
      const std::size_t end = text.find("*/", i + 2);
      advance_to(end == std::string::npos ? n : end + 2);
    } else if (c == '"' || c == '\'') {
      const int start_line = line;
      const std::size_t end = text.find(c, i + 1);
      const std::size_t stop = end == std::string::npos ? n : end;
      tokens.push_back({Token::kString, text.substr(i + 1, stop - i - 1), start_line});
      advance_to(stop + 1);
    } else if (word_start(c)) {
      std::size_t end = i;
      while (end < n && word_char(text[end])) ++end;
      tokens.push_back({Token::kWord, text.substr(i, end - i), line});
      i = end;
    } else if (std::isdigit(static_cast<unsigned char>(c))) {
      std::size_t end = i;
      while (end < n && (word_char(text[end]) || text[end] == '.')) ++end;
      tokens.push_back({Token::kNumber, text.substr(i, end - i), line});
      i = end;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      advance_to(i + 1);
    } else {
      const bool shift = c == '>' && i + 1 < n && text[i + 1] == '>';
      tokens.push_back({Token::kPunct, shift ? ">>" : std::string(1, c), line});
      i += shift ? 2 : 1;
    }
  }
  return tokens;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(located(path, "", "cannot read the geometry file"));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

[[noreturn]] void refuse(const std::string& path, int line, const std::string& statement, const std::string& why) {
  throw Error(path + ":" + std::to_string(line) + ": statement '" + statement + "' is not allowed in a Talus .geo (" +
              why + "; " + kSubset + ")");
}

bool inside(const fs::path& folder, const fs::path& file) {
  const fs::path relative = file.lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

class Scanner {
 public:
  explicit Scanner(const std::string& top) : folder_(fs::weakly_canonical(fs::absolute(top)).parent_path()) {}

  void scan(const std::string& path) {
    const fs::path canonical = fs::weakly_canonical(fs::absolute(path));
    std::string chain;
    for (const auto& [file, shown] : stack_) chain += shown + " -> ";
    for (const auto& [file, shown] : stack_)
      if (file == canonical)
        throw Error(located(path, "", "Include loop: " + chain + path + " (a .geo may not include itself)"));
    if (stack_.size() >= kMaxIncludeDepth)
      throw Error(located(path, "", "Includes nested deeper than " + std::to_string(kMaxIncludeDepth) + ": " + chain + path));
    stack_.emplace_back(canonical, path);
    check_tokens(path, tokens_of(read_text(path)));
    // gmsh reads FILE.opt after FILE when it exists, with the same parser.
    std::error_code error;
    if (fs::is_regular_file(path + ".opt", error)) scan(path + ".opt");
    stack_.pop_back();
  }

 private:
  void check_tokens(const std::string& path, const std::vector<Token>& t) {
    const auto& refused = refused_words();
    for (std::size_t k = 0; k < t.size(); ++k) {
      if (t[k].kind != Token::kWord) continue;
      const std::string& word = t[k].text;
      const bool option = k + 1 < t.size() && t[k + 1].kind == Token::kPunct && t[k + 1].text == ".";
      if (option && refused_option_category(word))
        refuse(path, t[k].line, word + "." + (k + 2 < t.size() ? t[k + 2].text : ""),
               "only Mesh.* and Geometry.* options may be set");
      if (const auto found = refused.find(word); found != refused.end()) refuse(path, t[k].line, word, found->second);
      if (word == "Printf" || word == "Error" || word == "Warning") check_redirect(path, t, k);
      if (word == "Include") include(path, t, k);
    }
  }

  // Printf("...", ...) > "file" and >> "file" write the file.
  static void check_redirect(const std::string& path, const std::vector<Token>& t, std::size_t k) {
    std::size_t j = k + 1;
    if (j >= t.size() || t[j].text != "(") return;
    int depth = 0;
    for (; j < t.size(); ++j) {
      if (t[j].kind != Token::kPunct) continue;
      if (t[j].text == "(") ++depth;
      if (t[j].text == ")" && --depth == 0) break;
    }
    if (j + 1 < t.size() && t[j + 1].kind == Token::kPunct && (t[j + 1].text == ">" || t[j + 1].text == ">>"))
      refuse(path, t[k].line, t[k].text + "(...) " + t[j + 1].text, "it writes a file");
  }

  void include(const std::string& path, const std::vector<Token>& t, std::size_t k) {
    const int line = t[k].line;
    if (k + 2 >= t.size() || t[k + 1].kind != Token::kString || t[k + 2].text != ";")
      refuse(path, line, "Include", "an Include must name its file as one plain string, Include \"part.geo\";");
    const std::string& name = t[k + 1].text;
    fs::path target = name;
    if (target.is_relative()) target = fs::path(path).parent_path() / target;  // as gmsh resolves it
    const fs::path canonical = fs::weakly_canonical(fs::absolute(target));
    if (!inside(folder_, canonical))
      refuse(path, line, "Include \"" + name + "\"",
             "it reaches outside the .geo's folder " + folder_.string() + "; included files must lie in it or below");
    std::error_code error;
    if (!fs::is_regular_file(canonical, error))
      throw Error(path + ":" + std::to_string(line) + ": Include \"" + name + "\": no such file");
    scan(target.string());
  }

  fs::path folder_;
  std::vector<std::pair<fs::path, std::string>> stack_;  // the Include chain: canonical, as named
};

}  // namespace

void check_geo_program(const std::string& geo_path) {
  std::error_code error;
  if (!fs::is_regular_file(geo_path, error)) return;
  Scanner(geo_path).scan(geo_path);
}

}  // namespace talus::preproc
