#include <cstdio>
#include "common/scene/reader.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "common/error.hpp"
#include "common/range.hpp"

namespace talus::scene_reader {
namespace {

std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

std::string join(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

}  // namespace

std::string nearest(const std::string& key, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::string::npos;
  for (const auto& candidate : candidates) {
    const std::size_t d = edit_distance(key, candidate);
    if (d < best_distance) best_distance = d, best = candidate;
  }
  return best_distance <= std::max<std::size_t>(2, key.size() / 3) ? best : "";
}

bool TableReader::has(const std::string& key) {
  if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.push_back(key);
  return table_ && table_->contains(key);
}

std::optional<double> TableReader::given_number(const std::string& key) {
  if (!has(key)) return std::nullopt;
  const auto value = (*table_)[key].value<double>();
  if (!value) fail(key, "expected a number");
  return *value;
}

double TableReader::number(const std::string& key, std::optional<double> fallback, double min, double max,
                           bool min_inclusive, bool max_inclusive) {
  const std::optional<double> value = given_number(key);
  if (!value) {
    if (!fallback) fail(key, "missing (a number is required)");
    return *fallback;
  }
  const std::string problem = NumberRange{min, max, min_inclusive, max_inclusive}.problem(*value);
  if (!problem.empty()) fail(key, problem);
  return *value;
}

double TableReader::any_number(const std::string& key, std::optional<double> fallback) {
  const std::optional<double> value = given_number(key);
  if (!value) {
    if (!fallback) fail(key, "missing (a number is required)");
    return *fallback;
  }
  return *value;
}

long TableReader::integer(const std::string& key, long fallback, long min, long max) {
  if (!has(key)) return fallback;
  const auto value = (*table_)[key].value<int64_t>();
  if (!value || !(*table_)[key].is_integer()) fail(key, "expected an integer");
  if (*value < min || *value > max)
    fail(key, "got " + std::to_string(*value) + ", expected an integer in [" + std::to_string(min) + ", " +
                  std::to_string(max) + "]");
  return static_cast<long>(*value);
}

std::string TableReader::text(const std::string& key, std::optional<std::string> fallback) {
  if (!has(key)) {
    if (!fallback) fail(key, "missing (a string is required)");
    return *fallback;
  }
  const auto value = (*table_)[key].value<std::string>();
  if (!value) fail(key, "expected a string");
  return *value;
}

bool TableReader::boolean(const std::string& key, bool fallback) {
  if (!has(key)) return fallback;
  // value<bool>() would take an integer too: 1 is not true here.
  const auto value = (*table_)[key].value<bool>();
  if (!value || !(*table_)[key].is_boolean()) fail(key, "expected true or false");
  return *value;
}

Eigen::Vector2d TableReader::vector2(const std::string& key, std::optional<Eigen::Vector2d> fallback) {
  if (!has(key)) {
    if (!fallback) fail(key, "missing (expected [x, y])");
    return *fallback;
  }
  const toml::array* array = (*table_)[key].as_array();
  if (!array || array->size() != 2) fail(key, "expected two numbers [x, y]");
  Eigen::Vector2d v;
  for (int i = 0; i < 2; ++i) {
    const auto x = (*array)[i].value<double>();
    if (!x || !std::isfinite(*x)) fail(key, "expected two finite numbers [x, y]");
    v[i] = *x;
  }
  return v;
}

std::vector<std::string> TableReader::strings(const std::string& key) {
  std::vector<std::string> out;
  const toml::array* list = array(key, "expected a list of strings");
  if (!list) return out;
  for (const auto& item : *list) {
    const auto s = item.value<std::string>();
    if (!s) fail(key, "expected a list of strings");
    out.push_back(*s);
  }
  return out;
}

const toml::table* TableReader::table(const std::string& key) {
  if (!has(key)) return nullptr;
  const toml::table* sub = (*table_)[key].as_table();
  if (!sub) fail(key, "expected a table");
  return sub;
}

const toml::array* TableReader::array(const std::string& key, const std::string& expected) {
  if (!has(key)) return nullptr;
  const toml::array* list = (*table_)[key].as_array();
  if (!list) fail(key, expected);
  return list;
}

void TableReader::finish() const {
  if (!table_) return;
  for (const auto& [key, node] : *table_) {
    const std::string name(key.str());
    if (std::find(known_.begin(), known_.end(), name) != known_.end()) continue;
    const std::string path = prefix_.empty() ? name : prefix_ + "." + name;
    const std::string suggestion = name.size() > 200 ? "" : nearest(name, known_);
    std::string message = "unknown key";
    if (!suggestion.empty()) message += " (did you mean '" + (prefix_.empty() ? "" : prefix_ + ".") + suggestion + "'?)";
    else if (!known_.empty()) message += " (valid keys here: " + join(known_) + ")";
    if (overridden_.count(path))
      throw Error(located(file_, "--set " + echoed(path), "no such scene key: " + message));
    throw Error(located(file_, echoed(path), message));
  }
}

void TableReader::fail(const std::string& key, const std::string& message) const {
  throw Error(located(file_, prefix_.empty() ? key : prefix_ + "." + key, message));
}

namespace {

// A plain word or path (crossed, mohr_coulomb, ../other.geo): letters, digits, '_', '-', '.' and
// '/', not starting like a number.
bool bare_word(const std::string& text) {
  if (text.empty() || !(std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_' || text[0] == '.' || text[0] == '/'))
    return false;
  return std::all_of(text.begin(), text.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '/';
  });
}

}  // namespace

void apply_override(toml::table& root, const std::string& assignment, const std::string& file,
                    std::set<std::string>& overridden) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0 || assignment[equals - 1] == '.')
    throw Error(located(file, "--set " + echoed(assignment), "expected KEY=VALUE, e.g. --set run.end_time=2.0"));
  const std::string key = assignment.substr(0, equals);
  const std::string value_text = assignment.substr(equals + 1);

  const std::string item = "--set " + echoed(assignment);
  // One TOML value on one line: "value = TEXT" parsed as a document would take
  // "0.2\n[run]\ncfl = 9" as a value and a table (and keep the value only).
  if (value_text.find_first_of("\n\r") != std::string::npos)
    throw Error(located(file, item, "expected one value on one line, got a line break in it"));
  // A bare word that TOML does not accept (crossed, delaunay, ../x.geo) is taken as a string;
  // anything else TOML does not accept is an error, not a string.
  toml::table parsed;
  try {
    parsed = toml::parse("value = " + value_text);
  } catch (const toml::parse_error& error) {
    if (!bare_word(value_text))
      throw Error(located(file, item,
                          "the value is not valid TOML (" + std::string(error.description()) +
                              "); text other than a plain word needs quotes: --set 'KEY=\"TEXT\"'"));
    parsed = toml::table{{"value", value_text}};
  }
  // Nothing after the value (its source ends at the last character that is not a space; columns
  // count characters, 9 of them before it in "value = ").
  if (const toml::node* value = parsed.get("value"); value && value->source().end.line == 1) {
    std::string text = value_text;
    while (!text.empty() && (text.back() == ' ' || text.back() == '\t')) text.pop_back();
    const long characters = std::count_if(text.begin(), text.end(), [](char c) { return (c & 0xC0) != 0x80; });
    if (parsed.size() != 1 || static_cast<long>(value->source().end.column) - 9 < characters)
      throw Error(located(file, item, "expected one value, got more after it"));
  }

  std::vector<std::string> parts;
  std::stringstream stream(key);
  for (std::string part; std::getline(stream, part, '.');) {
    if (part.empty()) throw Error(located(file, "--set " + echoed(assignment), "empty part in the dotted key"));
    parts.push_back(part);
  }
  toml::table* table = &root;
  std::string path;
  for (std::size_t i = 0; i + 1 < parts.size(); ++i) {
    path += (path.empty() ? "" : ".") + parts[i];
    toml::node* node = table->get(parts[i]);
    if (!node) node = &table->insert_or_assign(parts[i], toml::table{}).first->second;
    table = node->as_table();
    if (!table) throw Error(located(file, "--set " + echoed(assignment), "'" + echoed(path) + "' is not a table"));
  }
  const toml::node* value = parsed.get("value");
  if (!value)
    throw Error(located(file, "--set " + echoed(assignment), "expected KEY=VALUE, e.g. --set run.end_time=2.0"));
  table->insert_or_assign(parts.back(), *value);
  overridden.insert(key);
}

std::string echoed(const std::string& text) {
  const std::string out = escaped(text.substr(0, 80));
  return text.size() > 80 ? out + "... (" + std::to_string(text.size()) + " characters)" : out;
}

// Body and material names become HDF5 group names (bodies/NAME, materials/NAME) beside the
// list of names itself: keep them to plain words.
void check_name(const std::string& name, const std::string& item, const std::string& file) {
  const bool plain = !name.empty() && name.size() <= 64 && name != "names" &&
                     std::all_of(name.begin(), name.end(), [](unsigned char c) {
                       return std::isalnum(c) || c == '_' || c == '-';
                     });
  if (!plain)
    throw Error(located(file, item,
                        "expected a name of letters, digits, '_' or '-' (at most 64, and not 'names'), got '" +
                            echoed(name) + "'"));
}

}  // namespace talus::scene_reader
