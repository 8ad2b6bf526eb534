// The range of a number, as the input checks (scene, model, material) state it.
#pragma once
#include <string>

namespace talus {

// An interval of finite numbers; either end may be open, and may be +-infinity.
struct NumberRange {
  double min, max;
  bool min_inclusive = true, max_inclusive = true;

  // x is finite and in the interval.
  bool contains(double x) const;
  // "[0, 0.5)", "(0, inf]".
  std::string text() const;
  // "got X, expected a finite number in [min, max)"; empty when the range contains x.
  std::string problem(double x) const;
};

}  // namespace talus
