// Particles as bytes, for the messages of a distributed solve (domain.cpp: migration,
// repartitioning, gathering on rank 0): every field of the registry (particles.hpp), so that a
// new field migrates with the particles without a line here.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

#include "solver/step/particles.hpp"

namespace talus::solver {

// Elements of each registry field per particle (0 for an unused field, history_width for the
// history): the same on every rank, so a rank that holds no particle can still read a message.
std::vector<std::size_t> field_widths(const Particles& P);
// Sets the width of the field named `member` (FieldInfo::name) in `widths`: a field that only some
// steps fill (step_velocity), the same steps on every rank.
void set_width(std::vector<std::size_t>& widths, const char* member, std::size_t width);
// Appends particle p's fields to `out`.
void pack(const Particles& P, const std::vector<std::size_t>& widths, std::size_t p, std::string& out);
// Bytes of one packed particle.
std::size_t packed_size(const std::vector<std::size_t>& widths);
// Appends the particles packed in [begin, end) to Q.
void unpack_all(const char* begin, const char* end, const std::vector<std::size_t>& widths, Particles& Q);
// Appends particles `which` of P to Q, in that order.
void append_particles(const Particles& P, const std::vector<std::size_t>& widths, const std::vector<std::size_t>& which,
                      Particles& Q);

}  // namespace talus::solver
