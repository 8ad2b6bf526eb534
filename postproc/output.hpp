// Writing the postprocessor's outputs: a small JSON writer (no dependency) and CSV tables,
// each file replaced atomically (common/atomic_file.hpp: PATH.tmp, then a rename) so that a
// reader never sees half a file.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "postproc/circle_fit.hpp"
#include "postproc/slope_geometry.hpp"

namespace talus::postproc {

// Builds a JSON document in order; commas and indentation are handled here. Non-finite numbers
// and empty optionals become null. Keys and strings are escaped.
class JsonWriter {
 public:
  JsonWriter& begin_object();
  JsonWriter& end_object();
  JsonWriter& begin_array();
  JsonWriter& end_array();
  JsonWriter& key(const std::string& name);
  JsonWriter& value(double number);
  JsonWriter& value(std::optional<double> number);
  JsonWriter& value(long number);
  JsonWriter& value(bool flag);
  JsonWriter& value(const std::string& text);
  JsonWriter& value(const char* text) { return value(std::string(text)); }  // not the bool overload
  JsonWriter& null();
  // [[x, y], ...] on one line per point.
  JsonWriter& value(const Polyline& points);
  // {"xc_m": .., "yc_m": .., "r_m": ..}, or null.
  JsonWriter& value(const std::optional<Circle>& circle);
  const std::string& text() const { return text_; }

 private:
  JsonWriter& open(char bracket, bool is_object);  // begin_object, begin_array
  void before_value();
  void newline();
  std::string text_;
  struct Level {
    bool is_object;
    bool empty;
  };
  std::vector<Level> levels_;
  bool after_key_ = false;
};

// talus::write_text_atomically: `content` to PATH.tmp, renamed to PATH. Throws talus::Error
// naming the file.
void write_file_atomically(const std::string& path, const std::string& content);

// A CSV table with a header row; all columns of equal length. Written atomically.
void write_csv(const std::string& path, const std::vector<std::string>& header,
               const std::vector<std::vector<double>>& columns);

}  // namespace talus::postproc
