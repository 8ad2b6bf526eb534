// The solver's files: results.h5 (+ results.xdmf) written frame by frame as the run goes, by one
// process or by every rank of a distributed solve (ResultsWriter, RankFrames: results.hpp,
// results_parallel.hpp; docs/results-format.md), and checkpoint.h5, from which --restart
// continues bit for bit (checkpoint.hpp; docs/robustness.md). Both visit the particle-field
// registry (solver/step/particles.hpp), so a new written or checkpointed field needs no line here.
#pragma once
#include "solver/io/checkpoint.hpp"
#include "solver/io/results.hpp"
#include "solver/io/results_parallel.hpp"
