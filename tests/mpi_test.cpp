// One model across several MPI ranks (docs/scaling.md), through the talus binary: `talus solve
// MODEL --ranks N` starts N ranks with mpirun (--oversubscribe: 3 ranks on this 2-core
// machine). The frames of 1, 2 and 3 ranks agree within 1e-10 relative on the slope, the
// frictional box (contact) and the granular column; a checkpoint written by 2 ranks restarts
// on 3 and on 1; a run that fails on several ranks stops them all with one message.
// Skipped when the binary was built without MPI.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <unistd.h>

#include "common/h5.hpp"
#include "support/bad_input_table.hpp"
#include "support/test_support.hpp"

namespace talus {
namespace {

namespace fs = std::filesystem;
using testing::run_shell;
using testing::run_talus;
using testing::frame_difference;
using testing::ScratchDir;

// Meshes geometries/slope.toml with `settings` into DIR/model and solves it on one rank, one
// thread, into DIR/one (`expected_status`: 1 for a run that must fail). Returns the model's path.
std::string slope_on_one_rank(const ScratchDir& dir, const std::string& settings, int expected_status,
                              testing::CommandResult* solved = nullptr) {
  const auto meshed = run_talus("mesh " + testing::source_path("geometries/slope.toml") + " --quiet " + settings +
                                " --out " + dir.file("model"));
  EXPECT_EQ(meshed.status, 0) << meshed.output;
  const std::string model = dir.file("model/model.h5");
  const auto one = run_talus("solve " + model + " --threads 1 --quiet --out " + dir.file("one"));
  EXPECT_EQ(one.status, expected_status) << one.output;
  if (solved) *solved = one;
  return model;
}

class Mpi : public ::testing::Test {
 protected:
  void SetUp() override {
    if (testing::talus_version().find("(with MPI") == std::string::npos) GTEST_SKIP() << "talus was built without MPI";
  }
  // Meshes `scene` with `settings` into DIR/model and solves it on 1, 2 and 3 ranks (one
  // thread each); every rank count's frames must match one rank's within `tolerance`.
  void expect_same_frames(const std::string& scene, const std::string& settings, double tolerance) {
    const ScratchDir dir("mpi");
    const auto meshed = run_talus("mesh " + testing::source_path("geometries/" + scene) + " --quiet " + settings +
                                  " --out " + dir.file("model"));
    ASSERT_EQ(meshed.status, 0) << meshed.output;
    const std::string model = dir.file("model/model.h5");
    for (int ranks : {1, 2, 3}) {
      const auto solved = run_talus("solve " + model + " --threads 1 --ranks " + std::to_string(ranks) + " --out " +
                                    dir.file("r" + std::to_string(ranks)));
      ASSERT_EQ(solved.status, 0) << solved.output;
      if (ranks > 1) {
        EXPECT_NE(solved.output.find("on " + std::to_string(ranks) + " MPI ranks"), std::string::npos) << solved.output;
        std::string worst;
        const double difference =
            frame_difference(dir.file("r1/results.h5"), dir.file("r" + std::to_string(ranks) + "/results.h5"), worst);
        EXPECT_LE(difference, tolerance) << scene << " on " << ranks << " ranks: " << worst;
      }
    }
  }
};

TEST_F(Mpi, SlopeFramesOnTwoAndThreeRanksMatchOneRank) {
  // The default slope (Mohr-Coulomb, EVS) coarsened to 0.7 m elements, to t = 2 s: its failure
  // crosses the partitions.
  expect_same_frames("slope.toml", "--set mesh.size=0.7 --set run.end_time=2.0", 1e-10);
}

TEST_F(Mpi, CpdiSlopeFramesOnTwoAndThreeRanksMatchOneRank) {
  // The same with CPDI: a particle's domain reaches the nodes of the elements around its own,
  // which the halo holds (a missing node would give differences of the velocities themselves),
  // and its isolated-particle test reads node masses summed over the ranks. The frames' velocity
  // is the one the step moved each particle with, kept before it changes rank: read after the
  // migration through the new rank's grid, a particle's 9 nodes could include ones that rank had
  // not summed, and 3 ranks differed from 1 by up to 0.05 m/s at single frames.
  expect_same_frames("slope.toml", "--set mesh.size=0.7 --set run.end_time=2.0 --set run.shape_functions=cpdi", 1e-10);
}

TEST_F(Mpi, FrictionalBoxFramesOnTwoAndThreeRanksMatchOneRank) {
  // Two bodies in frictional contact: the block slides across the partitions, its particles
  // migrate and the ranks repartition. (Before the fixed particles' runs were rebuilt after a
  // sort, the block on 2 and 3 ranks drifted 0.4 in stress from t = 0.47 s.)
  expect_same_frames("box_incline.toml", "--set mesh.size=0.05 --set run.end_time=0.8", 1e-10);
}

TEST_F(Mpi, GranularColumnFramesOnTwoAndThreeRanksMatchOneRank) {
  expect_same_frames("column_collapse.toml", "--set mesh.size=0.01 --set run.end_time=0.4", 1e-10);
}

TEST_F(Mpi, RisingWaterWithSofteningFramesOnTwoAndThreeRanksMatchOneRank) {
  // The fields the water and softening add (pore pressure, the strength falling with eps_p) on
  // a slope that a table rising 10 m in 4 s brings down: it runs out about 9 m across the
  // partitions, and the sand softens to a residual 20 degrees.
  expect_same_frames("rising_water.toml",
                     "--set mesh.size=2.0 --set run.end_time=8 --set 'water.rise=[[0.0,0.0],[4.0,10.0]]' "
                     "--set materials.soil.softening_end=0.2 --set materials.soil.residual_friction_angle=20.0 "
                     "--set materials.soil.residual_cohesion=0.0",
                     1e-10);
}

TEST_F(Mpi, PlainMpirunGivesTheSameFrames) {
  // mpirun started by hand, as on a cluster: rank 0 alone prints and writes.
  const ScratchDir dir("mpi-plain");
  const std::string model = slope_on_one_rank(dir, "--set mesh.size=0.7 --set run.end_time=1.0", 0);
  const auto two = run_shell("mpirun -n 2 --oversubscribe --quiet" + std::string(geteuid() == 0 ? " --allow-run-as-root" : "") +
                             " " + TALUS_BINARY + " solve " + model + " --threads 1 --out " + dir.file("two"));
  ASSERT_EQ(two.status, 0) << two.output;
  EXPECT_NE(two.output.find("on 2 MPI ranks"), std::string::npos) << two.output;
  std::size_t summaries = 0;
  for (std::size_t at = two.output.find("solved:"); at != std::string::npos; at = two.output.find("solved:", at + 1))
    ++summaries;
  EXPECT_EQ(summaries, 1u) << "one summary, rank 0's:\n" << two.output;
  std::string worst;
  EXPECT_LE(frame_difference(dir.file("one/results.h5"), dir.file("two/results.h5"), worst), 1e-10) << worst;
}

TEST_F(Mpi, CheckpointOfTwoRanksRestartsOnThreeAndOnOne) {
  // SIGTERM to `talus solve --ranks 2` reaches the ranks (as SIGUSR2, through mpirun); they stop
  // after the same step with one checkpoint, which 3 ranks and 1 rank both continue.
  const ScratchDir dir("mpi-restart");
  const std::string model = slope_on_one_rank(dir, "--set mesh.size=0.25 --set run.end_time=3.0", 0);
  const fs::path parts = dir.file("parts");
  const std::string script = "( " + std::string(TALUS_BINARY) + " solve " + model +
                             " --threads 1 --ranks 2 --quiet --checkpoint-interval 0.1 --out " + parts.string() +
                             " & pid=$!; for i in $(seq 1 3000); do [ -f '" + (parts / "checkpoint.h5").string() +
                             "' ] && break; sleep 0.01; done; kill -TERM $pid; wait $pid; echo status=$? )";
  const auto stopped = run_shell(script);
  ASSERT_NE(stopped.output.find("status=143"), std::string::npos) << stopped.output;
  EXPECT_NE(stopped.output.find("interrupted by SIGTERM"), std::string::npos) << stopped.output;
  // Rank 0's one line (and the shell's status): nothing of mpirun's.
  EXPECT_EQ(stopped.output.rfind("talus: interrupted by SIGTERM", 0), 0u) << stopped.output;
  EXPECT_EQ(std::count(stopped.output.begin(), stopped.output.end(), '\n'), 2) << stopped.output;
  {
    const auto times = h5::read_doubles(h5::File::open_read((parts / "results.h5").string()), "frames/time");
    ASSERT_FALSE(times.empty());
    EXPECT_LT(times.back(), 2.0) << "the run was not stopped midway";
  }
  for (int ranks : {3, 1}) {
    const fs::path again = dir.file("again" + std::to_string(ranks));
    fs::copy(parts, again, fs::copy_options::recursive);
    const auto restarted = run_talus("solve " + model + " --threads 1 --quiet --restart --ranks " +
                                     std::to_string(ranks) + " --out " + again.string());
    ASSERT_EQ(restarted.status, 0) << restarted.output;
    std::string worst;
    EXPECT_LE(frame_difference(dir.file("one/results.h5"), (again / "results.h5").string(), worst), 1e-10)
        << "restarted on " << ranks << " ranks: " << worst;
  }
}

TEST_F(Mpi, AParticleLeavingTheDomainStopsEveryRankWithOneMessage) {
  const ScratchDir dir("mpi-fail");
  testing::CommandResult one;
  const std::string model =
      slope_on_one_rank(dir, "--set mesh.size=0.7 --set 'bodies.soil.initial_velocity=[30.0, 0.0]'", 1, &one);
  const auto three = run_talus("solve " + model + " --threads 1 --quiet --ranks 3 --out " + dir.file("three"));
  EXPECT_EQ(three.status, 1) << three.output;
  // The one rank's message, once, and nothing of mpirun's.
  EXPECT_EQ(three.output, one.output.substr(0, one.output.find(dir.file("one"))) +
                              three.output.substr(three.output.find(dir.file("three"))))
      << "one rank:\n" << one.output << "three ranks:\n" << three.output;
  EXPECT_NE(three.output.find("left the domain"), std::string::npos) << three.output;
}

TEST_F(Mpi, BadModelOnSeveralRanksGivesOneMessage) {
  const ScratchDir dir("mpi-bad");
  const std::string bad = dir.file("damaged.h5");
  ASSERT_EQ(run_shell("printf 'not an HDF5 file' > " + bad).status, 0);
  const auto result = run_talus("solve " + bad + " --ranks 2 --quiet --out " + dir.file("out"));
  EXPECT_EQ(result.status, 1) << result.output;
  // One line, rank 0's.
  EXPECT_EQ(result.output.rfind("talus: error: " + bad + ": ", 0), 0u) << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  EXPECT_FALSE(fs::exists(dir.file("out/results.h5")));
}

TEST_F(Mpi, MixedIntegrationIsRefusedOnSeveralRanksWithOneMessage) {
  // Mixed integration reads the fill of the cells across each cell's edges, which another rank
  // may hold: refused before any step, once, with nothing written.
  const ScratchDir dir("mpi-mixed");
  const auto meshed = run_talus("mesh " + testing::source_path("geometries/spring_mass.toml") + " --quiet --out " +
                                dir.path().string());
  ASSERT_EQ(meshed.status, 0) << meshed.output;
  const auto result = run_talus("solve " + dir.file("model.h5") + " --threads 1 --ranks 2 --quiet --out " +
                                dir.file("out"));
  EXPECT_EQ(result.status, 1) << result.output;
  EXPECT_NE(result.output.find("run.integration = \"mixed\" runs on one rank only"), std::string::npos)
      << result.output;
  EXPECT_EQ(std::count(result.output.begin(), result.output.end(), '\n'), 1) << result.output;
  EXPECT_FALSE(fs::exists(dir.file("out/results.h5")));
}

// ---- Faults of `--ranks` (issue 43): a killed driver, a killed rank ------------------------

// A shell script that starts `talus solve MODEL --ranks 2` into OUT in the background (its output
// in OUT.log), waits until its ranks run (found as mpirun's children, rank 0's pid first) and
// have written the first frame, and then runs `body` with $T, $driver, $mpirun, $ranks and the
// helpers `alive PIDS`, `gone PIDS` (waits up to 30 s for them to end: "gone" or "alive"),
// `ends` (prints ranks=gone and lock=free when the ranks have ended and released the lock) and
// `finish` (waits up to 60 s for the driver and prints its status=). Whatever it started is
// killed when the script ends, whether or not the ranks ever ran.
std::string ranks_script(const std::string& model, const std::string& out, const std::string& body) {
  return "exec 2>&1; T=" + std::string(TALUS_BINARY) + "; out=" + out + "; model=" + model + "\n" +
         "$T solve $model --ranks 2 --threads 1 -q --out $out > $out.log 2>&1 & driver=$!\n"
         "for i in $(seq 1 600); do mpirun=$(ps -o pid= --ppid $driver | tr -d ' '); [ -n \"$mpirun\" ] && break; "
         "sleep 0.05; done\n"
         "trap 'kill -9 $driver $mpirun $(ps -o pid= --ppid $mpirun) 2>/dev/null' EXIT\n"
         // the first frame written: every rank is in the solve, where SIGTERM stops after a step
         "for i in $(seq 1 1200); do [ -f $out/results.xdmf ] && break; sleep 0.05; done\n"
         "ranks=''; for p in $(ps -o pid= --ppid $mpirun); do\n"
         "  if tr '\\0' '\\n' < /proc/$p/environ | grep -qx OMPI_COMM_WORLD_RANK=0; then ranks=\"$p $ranks\"; "
         "else ranks=\"$ranks $p\"; fi; done\n"
         "alive() { for p in \"$@\"; do s=$(cut -d' ' -f3 /proc/$p/stat 2>/dev/null); [ -n \"$s\" ] && [ \"$s\" != Z ] && "
         "return 0; done; return 1; }\n"
         "gone() { for i in $(seq 1 600); do alive \"$@\" || { echo gone; return; }; sleep 0.05; done; echo alive; }\n"
         "ends() { echo ranks=$(gone $ranks); flock -n $out/.talus.lock true && echo lock=free; }\n"
         "finish() { i=0; while alive $driver && [ $i -lt 1200 ]; do sleep 0.05; i=$((i + 1)); done; "
         "kill -9 $driver 2>/dev/null; wait $driver; echo status=$?; }\n"
         "echo ranks=$ranks\n" +
         body;
}

// ranks_script on a slope that runs for minutes on two ranks (the faults come while it runs),
// meshed into DIR/model, solved into DIR/out.
testing::CommandResult ranks_fault(const ScratchDir& dir, const std::string& body) {
  const auto meshed = run_talus("mesh " + testing::source_path("geometries/slope.toml") +
                                " --quiet --set mesh.size=0.5 --set run.end_time=60 --set run.rest_ratio=0.0 --out " +
                                dir.file("model"));
  EXPECT_EQ(meshed.status, 0) << meshed.output;
  return run_shell(ranks_script(dir.file("model/model.h5"), dir.file("out"), body));
}

// What ranks_script's body printed, and rank 0's log: the ranks ended, stopping after a step with
// a checkpoint (as on SIGTERM), and the lock is free.
void expect_ranks_stopped_with_a_checkpoint(const testing::CommandResult& result, const std::string& out) {
  EXPECT_NE(result.output.find("ranks=gone"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("lock=free"), std::string::npos) << result.output;
  const std::string log = testing::read_text(out + ".log");
  EXPECT_NE(log.find("talus: interrupted by SIGTERM at step "), std::string::npos) << log;
  EXPECT_TRUE(fs::exists(out + "/checkpoint.h5"));
}

// `kill -9` of the driver (issue 43, item 1): before, mpirun and the ranks went on writing with the
// lock released, a second solve was let in, and the orphans then deleted its results.h5. Now the
// ranks hold the lock: with them stopped (SIGSTOP) while the driver dies, a second solve is
// refused; once they run again they stop after the step with a checkpoint, keeping the frames,
// and release the lock.
TEST_F(Mpi, AKilledDriversRanksKeepTheFolderLockedUntilTheyStop) {
  const ScratchDir dir("mpi-orphans");
  const auto result = ranks_fault(dir,
                                  "kill -STOP $ranks; kill -9 $driver; wait $driver\n"
                                  "$T solve $model --threads 1 -q --out $out; echo second=$?\n"
                                  "kill -CONT $ranks; ends\n");
  const std::string out = dir.file("out");
  EXPECT_NE(result.output.find("second=1"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find(out + ": another talus is writing into this folder (pid "), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("(MPI ranks: pid "), std::string::npos) << result.output;
  expect_ranks_stopped_with_a_checkpoint(result, out);
  const h5::File results = h5::File::open_read(out + "/results.h5");
  EXPECT_EQ(h5::get_int(results, "/", "complete"), 0);
  EXPECT_GE(h5::read_doubles(results, "frames/time").size(), 1u);
}

// Without SIGSTOP the ranks see the driver go (mpirun forwards the SIGUSR2 the driver's death
// sends it, and each rank watches its link to the driver) and stop within a step or so.
TEST_F(Mpi, AKilledDriversRanksStopByThemselves) {
  const ScratchDir dir("mpi-orphans-stop");
  expect_ranks_stopped_with_a_checkpoint(ranks_fault(dir, "kill -9 $driver; wait $driver; ends\n"), dir.file("out"));
  EXPECT_TRUE(fs::exists(dir.file("out/results.h5")));
}

// `kill -9` of one rank (issue 43, item 1): before, exit 137 and not a word (mpirun's --quiet).
// Now the driver names the rank and the signal, and exits 128 + its number.
TEST_F(Mpi, ARankKilledByASignalIsNamed) {
  const ScratchDir dir("mpi-killed-rank");
  const auto result = ranks_fault(dir,
                                  "set -- $ranks; victim=$2; echo victim=$victim\n"
                                  "kill -9 $victim; finish\n"
                                  "echo left=$(gone $ranks $mpirun)\n");
  const std::string out = dir.file("out");
  const auto at = result.output.find("victim=");
  ASSERT_NE(at, std::string::npos) << result.output;
  const std::string victim = result.output.substr(at + 7, result.output.find('\n', at) - at - 7);
  EXPECT_NE(result.output.find("status=137"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("left=gone"), std::string::npos) << result.output;
  const std::string log = testing::read_text(out + ".log");
  EXPECT_NE(log.find("talus: error: --ranks 2: rank 1 (pid " + victim + ") was killed by SIGKILL; mpirun stopped the "
                     "other ranks. " + out + "/results.h5 keeps the frames written before"),
            std::string::npos)
      << log;
  EXPECT_EQ(log.find("internal error"), std::string::npos) << log;
}

// An absurd initial state in a model (issue 43, item 4): on 2 ranks a generic blow-up before;
// now the message of one rank, naming the dataset, once.
TEST_F(Mpi, AnAbsurdInitialVelocityGivesOneRanksMessageOnTwo) {
  const ScratchDir dir("mpi-initial-state");
  const std::string solve = testing::meshed_model_row(dir.path(), [](const h5::File& f) {
    h5::Dims dims;
    std::vector<double> velocity = h5::read_doubles(f, "particles/velocity", &dims);
    velocity[0] = 1e308;
    h5::write(f, "particles/velocity", velocity, dims);
  });
  const auto one = run_talus(solve + " --threads 1 --quiet --out " + dir.file("one"));
  const auto two = run_talus(solve + " --threads 1 --quiet --ranks 2 --out " + dir.file("two"));
  EXPECT_EQ(one.status, 1) << one.output;
  EXPECT_EQ(two.status, 1) << two.output;
  EXPECT_NE(one.output.find("model.h5: particles/velocity: particle 0 moves at 1e+308 m/s"), std::string::npos)
      << one.output;
  EXPECT_EQ(two.output, one.output);
}

TEST(MpiOptions, RanksIsRefusedWhereNothingSolves) {
  const auto result = run_talus("post nowhere.h5 --ranks 2");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.output.find("--ranks belongs to solve, run or ensemble, not post"), std::string::npos) << result.output;
  const auto zero = run_talus("solve nowhere.h5 --ranks 0");
  EXPECT_EQ(zero.status, 1);
  EXPECT_NE(zero.output.find("--ranks: expected an integer from 1 to 256, got '0'"), std::string::npos) << zero.output;
}

}  // namespace
}  // namespace talus
