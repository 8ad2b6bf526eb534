// User-facing errors. Every bad input becomes one talus::Error whose message names the file,
// the item and what was expected; the driver prints it once and exits with status 1.
#pragma once
#include <stdexcept>
#include <string>

namespace talus {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// An error every rank of a distributed solve throws alike, at the same point (a blow-up, a
// particle leaving the domain, bad input all ranks read): the driver prints it on rank 0 only
// and every rank exits with status 1. Any other Error in a distributed solve is one rank's, and
// stops all ranks at once (solver/parallel/mpi.hpp, abort_all). With one rank it is a plain Error.
struct SharedError : Error {
  using Error::Error;
};

// `text` with its control characters shown as \xNN (a newline as \x0a): input quoted in a
// message stays on its line.
std::string escaped(const std::string& text);

// "file: item: message", leaving out the parts that are empty; control characters in the file and
// the item (which come from input) are shown as \xNN.
std::string located(const std::string& file, const std::string& item, const std::string& message);

}  // namespace talus
