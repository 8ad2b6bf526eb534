// The files of `talus ensemble` (docs/ensemble.md): realisations.csv (one row per realisation,
// numbers to 17 significant digits so that a row read back and written again is the same text),
// and ensemble.json, the statistics over the rows.
#pragma once
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "workflow/ensemble_realisation.hpp"
#include "workflow/ensemble_statistics.hpp"

namespace talus::workflow {

// The first line of realisations.csv: the fingerprint of what the rows depend on (the scene
// after --set, its .geo, the program, --fos and its tolerance), then the header, with a column
// mean_NAME per field and, with `fos` (--fos), a column fos.
std::string csv_preamble(std::uint64_t inputs, const std::vector<std::string>& fields, bool fos = false);
std::string csv_line(const RealisationRow& row, bool fos = false);
// One line of csv_line's (without its newline) read back; empty when it is not one of `fields`
// (and `fos`) columns.
std::optional<RealisationRow> parse_csv_line(const std::string& line, std::size_t fields, bool fos = false);

// The rows of realisations.csv whose fingerprint is `inputs`, by seed; a line cut short (a
// process killed while writing it) or unreadable is left out and counted in `dropped`. Empty
// when the file is missing or of other inputs.
std::map<std::uint64_t, RealisationRow> read_rows(const std::string& path, std::uint64_t inputs,
                                                  const std::vector<std::string>& fields, long& dropped,
                                                  bool fos = false);

// realisations.csv with `rows` in seed order, written atomically.
void write_rows(const std::string& path, std::uint64_t inputs, const std::vector<std::string>& fields,
                const std::vector<RealisationRow>& rows, bool fos = false);

// What ensemble.json reports besides the rows.
struct EnsembleRun {
  std::uint64_t seed = 0;  // S
  long realisations = 0;   // N
  int jobs = 1;            // realisations at once on each rank
  int ranks = 1;           // MPI ranks (--ranks)
  std::optional<double> fos_tolerance;  // --fos: the search's bracket width
  double mesh_seconds = 0;
  // This invocation's realisations only (a resumed ensemble's earlier ones are not timed).
  long timed = 0;
  double field_seconds = 0;   // drawing the fields and setting the properties
  double solve_seconds = 0;   // building the simulation and the time loop
  double post_seconds = 0;    // the runout, the slip surface and the time to rest
  double fos_seconds = 0;     // --fos: the factor of safety's equilibrium and search
  double record_seconds = 0;  // appending the rows to realisations.csv
  double wall_seconds = 0;    // from the first realisation started to the last finished
};

// ensemble.json's text.
std::string ensemble_json(const EnsembleModel& ensemble, const EnsembleRun& run, const std::vector<RealisationRow>& rows);

}  // namespace talus::workflow
