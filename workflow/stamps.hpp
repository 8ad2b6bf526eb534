// What `talus run` needs to re-run only the stages whose inputs changed. Each stage has a
// fingerprint of its inputs, chained: mesh = (scene after --set, .geo, program); solve =
// (mesh's, program); post = (solve's, program, figures script). `talus run` records them in
// OUT/.talus-stamps after each stage and skips a stage whose output exists with the same
// fingerprint. Running a single stage by hand forgets the folder's stamps.
#pragma once
#include <cstdint>
#include <string>

#include "common/fingerprint.hpp"

namespace talus::stamps {

// A Fingerprint (FNV-1a) over a string, and over a file's bytes (a missing file hashes as its
// name), continuing from `seed`.
uint64_t hash(const std::string& text, uint64_t seed = Fingerprint::kStart);
uint64_t hash_file(const std::string& path, uint64_t seed = Fingerprint::kStart);

// The running program's executable.
uint64_t program();

// The fingerprint recorded for `stage` in `folder`, or 0.
uint64_t recorded(const std::string& folder, const std::string& stage);
void record(const std::string& folder, const std::string& stage, uint64_t fingerprint);
void forget(const std::string& folder);

}  // namespace talus::stamps
