#include "workflow/ranks_link.hpp"

#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <random>
#include <sstream>
#include <thread>

#include "common/error.hpp"
#include "solver/parallel/mpi.hpp"

namespace talus::workflow {
namespace {

// The address of an abstract socket: a NUL byte, then the name (no file on disk).
socklen_t abstract_address(const std::string& name, sockaddr_un& address) {
  address = {};
  address.sun_family = AF_UNIX;
  const std::size_t length = std::min(name.size(), sizeof address.sun_path - 1);
  std::memcpy(address.sun_path + 1, name.data(), length);
  return static_cast<socklen_t>(offsetof(sockaddr_un, sun_path) + 1 + length);
}

bool send_text(int fd, const std::string& text) {
  return send(fd, text.data(), text.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(text.size());
}

// The descriptor a rank holds for the folder lock, and its connection to the driver.
int held_lock = -1;
int driver_connection = -1;

}  // namespace

RanksListener::RanksListener(int lock_fd) : lock_fd_(lock_fd) {
  std::random_device random;
  name_ = "talus-ranks-" + std::to_string(getpid()) + "-" + std::to_string(random());
  listen_fd_ = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  sockaddr_un address;
  const socklen_t length = abstract_address(name_, address);
  if (listen_fd_ < 0 || bind(listen_fd_, reinterpret_cast<sockaddr*>(&address), length) != 0 ||
      listen(listen_fd_, 256) != 0) {
    const std::string why = std::strerror(errno);
    if (listen_fd_ >= 0) close(listen_fd_);
    throw Error("--ranks: cannot open the socket the ranks join the folder's lock by: " + why);
  }
  char text[400] = {};
  const ssize_t n = pread(lock_fd_, text, sizeof text - 1, 0);
  holder_.assign(text, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!holder_.empty() && (holder_.back() == '\n' || holder_.back() == '\0')) holder_.pop_back();
}

RanksListener::~RanksListener() {
  for (const Peer& peer : peers_)
    if (peer.fd >= 0) close(peer.fd);
  if (listen_fd_ >= 0) close(listen_fd_);
}

void RanksListener::serve(int timeout_ms) {
  std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
  for (const Peer& peer : peers_)
    if (peer.fd >= 0) fds.push_back({peer.fd, POLLIN, 0});
  if (poll(fds.data(), fds.size(), timeout_ms) <= 0) return;  // nothing, or a signal (EINTR)
  if (fds[0].revents & POLLIN) accept_ranks();
  // In the order of the peers, which is the order the events are looked at: connections that
  // closed in one wake-up are told apart by the pid order only (they ended within microseconds).
  for (Peer& peer : peers_)
    if (peer.fd >= 0) read_from(peer);
}

void RanksListener::accept_ranks() {
  for (;;) {
    const int fd = accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC | SOCK_NONBLOCK);
    if (fd < 0) return;
    // Only this user's processes get the lock (the abstract namespace is the machine's).
    ucred credentials{};
    socklen_t size = sizeof credentials;
    if (getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &credentials, &size) != 0 || credentials.uid != geteuid()) {
      close(fd);
      continue;
    }
    Peer peer;
    peer.fd = fd;
    peer.pid = credentials.pid;
    peers_.push_back(peer);
  }
}

void RanksListener::read_from(Peer& peer) {
  for (;;) {
    char buffer[128];
    const ssize_t n = recv(peer.fd, buffer, sizeof buffer - 1, MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
    if (n <= 0) {  // closed: the rank has ended
      close(peer.fd);
      peer.fd = -1;
      peer.ended = ended_++;
      return;
    }
    std::istringstream words(std::string(buffer, static_cast<std::size_t>(n)));
    std::string word;
    words >> word;
    if (word == "hello") {
      words >> peer.rank;
      // The lock itself, as ancillary data.
      char control[CMSG_SPACE(sizeof(int))] = {};
      char tag[] = "lock";
      iovec data{tag, 4};
      msghdr message{};
      message.msg_iov = &data;
      message.msg_iovlen = 1;
      message.msg_control = control;
      message.msg_controllen = sizeof control;
      cmsghdr* header = CMSG_FIRSTHDR(&message);
      header->cmsg_level = SOL_SOCKET;
      header->cmsg_type = SCM_RIGHTS;
      header->cmsg_len = CMSG_LEN(sizeof(int));
      std::memcpy(CMSG_DATA(header), &lock_fd_, sizeof(int));
      sendmsg(peer.fd, &message, MSG_NOSIGNAL);  // a rank that does not get it stops
      write_holder();
    } else if (word == "bye") {
      words >> peer.status;
      peer.said_bye = true;
      if (peer.status != 0 && failed_bye_order_ < 0) failed_bye_order_ = ended_;
    }
  }
}

// "pid D: talus solve ... (MPI ranks: pid A, pid B)": what a second talus is told.
void RanksListener::write_holder() const {
  std::string text = holder_;
  std::string pids;
  for (const Peer& peer : peers_)
    if (peer.rank >= 0) pids += (pids.empty() ? "" : ", ") + std::string("pid ") + std::to_string(peer.pid);
  if (!pids.empty()) text += " (MPI ranks: " + pids + ")";
  text += "\n";
  const bool told = ftruncate(lock_fd_, 0) == 0 && pwrite(lock_fd_, text.data(), text.size(), 0) > 0;
  static_cast<void>(told);  // only for the message of a second writer
}

int RanksListener::killed_rank() const {
  const Peer* first = nullptr;
  for (const Peer& peer : peers_)
    if (peer.ended >= 0 && !peer.said_bye && (!first || peer.ended < first->ended)) first = &peer;
  if (!first) return -1;
  // A rank that failed and said so came first: the others were stopped because of it.
  if (failed_bye_order_ >= 0 && failed_bye_order_ <= first->ended) return -1;
  return first->rank;
}

long RanksListener::pid_of(int rank) const {
  for (const Peer& peer : peers_)
    if (peer.rank == rank) return peer.pid;
  return 0;
}

std::string join_ranks_driver() {
  const char* name = std::getenv(kRanksSocketVariable);
  if (!name || !*name) return "its environment does not name the driver's socket (" + std::string(kRanksSocketVariable) + ")";
  const int fd = socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
  sockaddr_un address;
  const socklen_t length = abstract_address(name, address);
  if (fd < 0 || connect(fd, reinterpret_cast<sockaddr*>(&address), length) != 0) {
    const std::string why = std::strerror(errno);
    if (fd >= 0) close(fd);
    return "cannot reach the `talus --ranks` process that started it (" + why + "): it is gone";
  }
  // The driver answers within a few of its 50 ms rounds; a minute covers a machine under load.
  timeval wait{60, 0};
  setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &wait, sizeof wait);
  const std::string hello = "hello " + std::to_string(solver::mpi::rank()) + " " + std::to_string(getpid());
  char tag[8] = {};
  char control[CMSG_SPACE(sizeof(int))] = {};
  iovec data{tag, sizeof tag};
  msghdr message{};
  message.msg_iov = &data;
  message.msg_iovlen = 1;
  message.msg_control = control;
  message.msg_controllen = sizeof control;
  const ssize_t n = send_text(fd, hello) ? recvmsg(fd, &message, MSG_CMSG_CLOEXEC) : -1;
  const cmsghdr* header = n > 0 ? CMSG_FIRSTHDR(&message) : nullptr;
  if (!header || header->cmsg_level != SOL_SOCKET || header->cmsg_type != SCM_RIGHTS) {
    close(fd);
    return "the `talus --ranks` process that started it did not hand over the folder's lock: it is gone";
  }
  std::memcpy(&held_lock, CMSG_DATA(header), sizeof(int));
  driver_connection = fd;
  // The driver's end: when its side closes, this rank stops as if sent SIGTERM (after the step,
  // with a checkpoint; before the time loop, at once, having written nothing).
  std::thread([fd] {
    pollfd watched{fd, POLLIN | POLLRDHUP, 0};
    while (poll(&watched, 1, -1) < 0 && errno == EINTR) {
    }
    kill(getpid(), SIGTERM);
  }).detach();
  return "";
}

void tell_ranks_driver_exit(int status) {
  if (driver_connection >= 0) send_text(driver_connection, "bye " + std::to_string(status));
}

}  // namespace talus::workflow
