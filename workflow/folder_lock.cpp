#include "workflow/folder_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.hpp"

namespace talus::workflow {
namespace {

// "pid N: talus solve out/x/model.h5", from /proc/self/cmdline, at most 300 characters.
std::string holder_text() {
  std::ifstream in("/proc/self/cmdline", std::ios::binary);
  std::string command;
  for (std::string word; std::getline(in, word, '\0');) command += (command.empty() ? "" : " ") + word;
  if (command.size() > 300) command = command.substr(0, 300) + "...";
  for (char& c : command)
    if (static_cast<unsigned char>(c) < 0x20) c = ' ';
  return "pid " + std::to_string(getpid()) + ": " + command;
}

std::string read_holder(int fd) {
  char buffer[400] = {};
  const ssize_t n = pread(fd, buffer, sizeof buffer - 1, 0);
  std::string text(buffer, n > 0 ? static_cast<std::size_t>(n) : 0);
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  return text.empty() ? "a process that has not said who it is" : text;
}

}  // namespace

FolderLock::FolderLock(const std::string& folder) {
  const std::string path = (std::filesystem::path(folder) / ".talus.lock").string();
  fd_ = open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
  if (fd_ < 0)
    throw Error(located(path, "", std::string("cannot create the folder's lock file: ") + std::strerror(errno) +
                                      " (is the folder writable?)"));
  if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    const std::string holder = error == EWOULDBLOCK ? read_holder(fd_) : "";
    close(fd_);
    fd_ = -1;
    if (error != EWOULDBLOCK)
      throw Error(located(path, "", std::string("cannot lock the folder: ") + std::strerror(error)));
    throw Error(located(folder, "", "another talus is writing into this folder (" + holder +
                                        "); wait for it to end, or choose another --out"));
  }
  const std::string text = holder_text() + "\n";
  // Who holds it is only for the message of a second writer: a failure here changes nothing.
  const bool told = ftruncate(fd_, 0) == 0 && pwrite(fd_, text.data(), text.size(), 0) > 0;
  static_cast<void>(told);
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  const bool cleared = ftruncate(fd_, 0) == 0;
  static_cast<void>(cleared);
  close(fd_);  // releases the lock
}

}  // namespace talus::workflow
