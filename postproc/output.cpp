#include "postproc/output.hpp"

#include <cmath>
#include <cstdio>

#include "common/atomic_file.hpp"

namespace talus::postproc {
namespace {

std::string number_text(double number) {
  if (!std::isfinite(number)) return "null";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.10g", number);
  return buffer;
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (unsigned char c : text) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
          out += buffer;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

}  // namespace

void JsonWriter::newline() {
  text_ += '\n';
  text_.append(2 * levels_.size(), ' ');
}

void JsonWriter::before_value() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  if (levels_.empty()) return;
  if (!levels_.back().empty) text_ += levels_.back().is_object ? "," : ", ";
  if (levels_.back().is_object) newline();
  levels_.back().empty = false;
}

JsonWriter& JsonWriter::open(char bracket, bool is_object) {
  before_value();
  text_ += bracket;
  levels_.push_back({is_object, true});
  return *this;
}

JsonWriter& JsonWriter::begin_object() { return open('{', true); }

JsonWriter& JsonWriter::end_object() {
  const bool empty = levels_.back().empty;
  levels_.pop_back();
  if (!empty) newline();
  text_ += '}';
  if (levels_.empty()) text_ += '\n';
  return *this;
}

JsonWriter& JsonWriter::begin_array() { return open('[', false); }

JsonWriter& JsonWriter::end_array() {
  levels_.pop_back();
  text_ += ']';
  return *this;
}

JsonWriter& JsonWriter::key(const std::string& name) {
  before_value();
  text_ += quoted(name) + ": ";
  after_key_ = true;
  return *this;
}

JsonWriter& JsonWriter::value(double number) {
  before_value();
  text_ += number_text(number);
  return *this;
}

JsonWriter& JsonWriter::value(std::optional<double> number) { return number ? value(*number) : null(); }

JsonWriter& JsonWriter::value(long number) {
  before_value();
  text_ += std::to_string(number);
  return *this;
}

JsonWriter& JsonWriter::value(bool flag) {
  before_value();
  text_ += flag ? "true" : "false";
  return *this;
}

JsonWriter& JsonWriter::value(const std::string& text) {
  before_value();
  text_ += quoted(text);
  return *this;
}

JsonWriter& JsonWriter::null() {
  before_value();
  text_ += "null";
  return *this;
}

JsonWriter& JsonWriter::value(const std::optional<Circle>& circle) {
  if (!circle) return null();
  return begin_object()
      .key("xc_m").value(circle->centre.x())
      .key("yc_m").value(circle->centre.y())
      .key("r_m").value(circle->radius)
      .end_object();
}

JsonWriter& JsonWriter::value(const Polyline& points) {
  begin_array();
  for (const auto& p : points) begin_array().value(p.x()).value(p.y()).end_array();
  return end_array();
}

void write_file_atomically(const std::string& path, const std::string& content) {
  write_text_atomically(path, content);
}

void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns) {
  std::string text;
  for (std::size_t c = 0; c < header.size(); ++c) text += (c ? "," : "") + header[c];
  text += '\n';
  const std::size_t rows = columns.empty() ? 0 : columns.front().size();
  for (std::size_t r = 0; r < rows; ++r) {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (c) text += ',';
      const double v = columns[c][r];
      // CSV readers (numpy, pandas) take "nan" for a missing number; JSON's null has no place here.
      text += std::isfinite(v) ? number_text(v) : "nan";
    }
    text += '\n';
  }
  write_file_atomically(path, text);
}

}  // namespace talus::postproc
