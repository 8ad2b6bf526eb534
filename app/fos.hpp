// `talus fos SCENE`: factor of safety by shear strength reduction with MPM (docs/fos.md).
// Writes OUT/fos.json, OUT/fos_particles.csv and the figure OUT/fos.png.
#pragma once
#include "app/cli.hpp"

namespace talus {

// Options: --set KEY=VALUE, --out DIR, --threads N (parallel trials, one core each),
// --tolerance=DF (bracket width, default 0.01), --quiet. Returns the exit status.
int run_fos(const cli::Arguments& args);

}  // namespace talus
