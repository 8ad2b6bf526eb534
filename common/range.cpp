#include "common/range.hpp"

#include <cmath>
#include <sstream>

namespace talus {
namespace {

std::string bound(double x) {
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

bool NumberRange::contains(double x) const {
  const bool below = min_inclusive ? x < min : x <= min;
  const bool above = max_inclusive ? x > max : x >= max;
  return std::isfinite(x) && !below && !above;
}

std::string NumberRange::text() const {
  return (min_inclusive ? "[" : "(") + bound(min) + ", " + bound(max) + (max_inclusive ? "]" : ")");
}

std::string NumberRange::problem(double x) const {
  if (contains(x)) return "";
  std::ostringstream message;
  message << "got " << x << ", expected a finite number in " << text();
  return message.str();
}

}  // namespace talus
