// The link between a `--ranks` driver and the ranks it starts under mpirun (workflow/launch.hpp).
//
// mpirun closes every inherited descriptor in the ranks it starts, so the ranks cannot inherit
// the output folder's lock. The driver listens on a Unix socket of the abstract namespace
// (named in the ranks' environment, kRanksSocketVariable); each rank connects before it
// touches the folder, says its rank and pid, and receives the lock's own descriptor (SCM_RIGHTS:
// the same open file, so the same flock), which it keeps open until it exits. The lock is then
// released only when the driver and every rank have gone: a `kill -9` of the driver leaves it
// held by the ranks, and a second talus aimed at the folder is refused while any of them lives.
//
// The connection tells each side when the other has gone. A rank watches it from a thread of
// its own: when the driver is gone, the rank sends itself SIGTERM, which a solve takes as a
// request to stop after the step with a checkpoint (solver.hpp). The driver learns from it which
// rank ended first and whether it ended on its own (a rank says "bye STATUS" as it exits) or was
// killed (its connection closed without a word): mpirun's own report is silenced by --quiet.
#pragma once
#include <string>
#include <vector>

namespace talus::workflow {

// The variable naming the driver's socket in the ranks' environment.
constexpr const char* kRanksSocketVariable = "TALUS_RANKS_SOCKET";

// The driver's end: listens while it lives, serves the ranks while mpirun runs.
class RanksListener {
 public:
  // Listens on a fresh abstract socket; `lock_fd` is the folder lock handed to each rank (the
  // ranks' pids are added to the holder text in its file as they join).
  explicit RanksListener(int lock_fd);
  ~RanksListener();
  RanksListener(const RanksListener&) = delete;
  RanksListener& operator=(const RanksListener&) = delete;

  const std::string& name() const { return name_; }
  // Accepts ranks, answers them and notes what they say or that they closed, waiting at most
  // `timeout_ms` for the first event.
  void serve(int timeout_ms);

  // The first rank whose connection closed before it said bye, unless a rank had already said
  // bye with a failure (it has told the user why): -1 when none.
  int killed_rank() const;
  long pid_of(int rank) const;

 private:
  struct Peer {
    int fd = -1;
    int rank = -1;
    long pid = 0;
    int ended = -1;       // the order in which its connection closed; -1 while open
    bool said_bye = false;
    int status = 0;       // what it said in its bye
  };
  void accept_ranks();
  void read_from(Peer& peer);
  void write_holder() const;

  int listen_fd_ = -1;
  int lock_fd_ = -1;
  std::string name_;
  std::string holder_;
  std::vector<Peer> peers_;
  int ended_ = 0;              // connections closed so far
  int failed_bye_order_ = -1;  // connections closed when the first bye with a failure came
};

// On a rank started by a `--ranks` driver: connects to it, takes the folder's lock from it and
// starts the watch for its end. Returns "" on success, else why it failed (the driver is gone).
std::string join_ranks_driver();

// On a rank that joined: tells the driver it exits with `status`, on its own.
void tell_ranks_driver_exit(int status);

}  // namespace talus::workflow
