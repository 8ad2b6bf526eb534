// One hashing facility: a 64-bit FNV-1a fingerprint of whatever is added to it, in order.
// For telling whether inputs changed (talus run's stage stamps, a checkpoint's model), not for
// security. The value depends on the bytes of the machine's representation (doubles and
// integers as stored in memory), which is what a fingerprint on one machine needs.
//
// The default start, kStart = 1469598103934665603, is not FNV's offset basis
// (14695981039346656037, one digit longer): it is the value Talus has always started from, so
// the fingerprints in existing checkpoint.h5 files stay valid. Any start tells inputs apart.
//
//   Fingerprint f;
//   f.add(model.nodes).add(model.triangles).add(model.mass).add(model.run.cfl).add(model.scene_name);
//   const uint64_t value = f.value();
#pragma once
#include <Eigen/Core>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

namespace talus {

class Fingerprint {
 public:
  static constexpr uint64_t kStart = 1469598103934665603ull;  // see above
  static constexpr uint64_t kPrime = 1099511628211ull;          // FNV's 64-bit prime

  // seed: a fingerprint to continue from (chaining), or Talus's start.
  explicit Fingerprint(uint64_t seed = kStart) : hash_(seed) {}

  // Raw bytes.
  Fingerprint& add(const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash_ = (hash_ ^ bytes[i]) * kPrime;
    return *this;
  }

  // The bytes of the elements (not the length) of a vector of plain values, such as doubles,
  // int32_t or std::array<int32_t, 3>, or of fixed-size Eigen vectors (the same bytes as the
  // vector flattened into its coordinates).
  template <class T>
    requires std::is_trivially_copyable_v<T>
  Fingerprint& add(const std::vector<T>& values) {
    return add(values.data(), values.size() * sizeof(T));
  }
  template <class Scalar, int Rows>
  Fingerprint& add(const std::vector<Eigen::Matrix<Scalar, Rows, 1>>& values) {
    static_assert(Rows > 0 && sizeof(Eigen::Matrix<Scalar, Rows, 1>) == Rows * sizeof(Scalar),
                  "fixed-size, unpadded vectors only");
    return add(values.data(), values.size() * sizeof(Scalar) * Rows);
  }

  Fingerprint& add(double value) { return add(&value, sizeof value); }
  // Any integer (and bool) is added as the 8 bytes of an int64_t.
  template <std::integral Integer>
  Fingerprint& add(Integer value) {
    const int64_t wide = static_cast<int64_t>(value);
    return add(&wide, sizeof wide);
  }

  // A string's characters (not its length): add(text) and add(text.data(), text.size()) agree.
  Fingerprint& add(const std::string& text) { return add(text.data(), text.size()); }
  Fingerprint& add(const char* text) { return add(std::string(text)); }
  // A list of strings: each one's length, then its characters, so that {"ab", "c"} and
  // {"a", "bc"} differ.
  Fingerprint& add(const std::vector<std::string>& texts) {
    for (const auto& text : texts) add(text.size()).add(text);
    return *this;
  }

  // A file's bytes. Returns false, adding nothing, when the file cannot be opened.
  bool add_file(const std::string& path);

  uint64_t value() const { return hash_; }

 private:
  uint64_t hash_;
};

}  // namespace talus
