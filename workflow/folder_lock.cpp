#include "workflow/folder_lock.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>

#include "common/error.hpp"

namespace talus::workflow {
namespace {

namespace fs = std::filesystem;

// The folders create_output_folder made, by the name it was given: the outermost folder it
// created for each (a parent, when the parents were missing too).
std::mutex made_mutex;
std::map<std::string, std::string> made_folders;

// The locks this process holds, by folder name.
std::map<std::string, FolderLock*> held_locks;

std::string made_root(const std::string& folder) {
  const std::lock_guard<std::mutex> guard(made_mutex);
  const auto it = made_folders.find(folder);
  return it == made_folders.end() ? std::string() : it->second;
}

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

void create_output_folder(const std::string& folder) {
  if (folder.empty()) throw Error("--out: expected a folder, got an empty name");
  std::error_code error;
  // The outermost missing folder of the path: what this call will have made.
  fs::path root;
  for (fs::path p = fs::absolute(folder, error); !error && !p.empty(); p = p.parent_path()) {
    struct stat st {};
    if (lstat(p.c_str(), &st) == 0 || errno != ENOENT) break;
    root = p;
    if (p == p.parent_path()) break;
  }
  error.clear();
  fs::create_directories(folder, error);
  if (!error && !fs::is_directory(folder, error)) error = std::make_error_code(std::errc::not_a_directory);
  if (error) throw Error(located(folder, "", "cannot use this as the output folder: " + error.message()));
  if (!root.empty()) {
    const std::lock_guard<std::mutex> guard(made_mutex);
    made_folders[folder] = root.string();
  }
}

FolderLock::FolderLock(const std::string& folder)
    : folder_(folder), created_root_(made_root(folder)), exceptions_(std::uncaught_exceptions()) {
  const std::string path = (fs::path(folder) / ".talus.lock").string();
  // A failed stage may remove a lock file it made (remove_if_left_empty): a lock taken on a file
  // that is no longer the folder's is no lock, so it is taken again on the file that is.
  for (int attempt = 0;; ++attempt) {
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
    struct stat held {}, named {};
    if (fstat(fd_, &held) == 0 && stat(path.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino)
      break;
    close(fd_);
    fd_ = -1;
    if (attempt == 10) throw Error(located(path, "", "the lock file keeps being replaced; is another program removing it?"));
  }
  {
    const std::lock_guard<std::mutex> guard(made_mutex);
    held_locks[folder_] = this;
  }
  const std::string text = holder_text() + "\n";
  // Who holds it is only for the message of a second writer: a failure here changes nothing.
  const bool told = ftruncate(fd_, 0) == 0 && pwrite(fd_, text.data(), text.size(), 0) > 0;
  static_cast<void>(told);
}

// Called while the lock is held: the lock file goes first, so a talus that opened it meanwhile
// finds it is no longer the folder's (the check in the constructor).
void FolderLock::remove_if_left_empty() {
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder_, error))
    if (entry.path().filename() != ".talus.lock") return;
  if (error) return;
  fs::remove(fs::path(folder_) / ".talus.lock", error);
  if (error) return;
  // The folder and the parents made for it, innermost first, while they are empty.
  const fs::path root = fs::path(created_root_);
  for (fs::path p = fs::absolute(folder_, error); !error && !p.empty(); p = p.parent_path()) {
    if (!fs::remove(p, error) || error) return;
    if (p == root || p == p.parent_path()) return;
  }
}

int FolderLock::held_descriptor(const std::string& folder) {
  const std::lock_guard<std::mutex> guard(made_mutex);
  const auto it = held_locks.find(folder);
  return it == held_locks.end() ? -1 : it->second->fd_;
}

void FolderLock::release_all_after_fatal_error() {
  // No lock taken here: the process is ending, and the thread that failed may hold it.
  for (const auto& [folder, lock] : held_locks)
    if (!lock->created_root_.empty()) lock->remove_if_left_empty();
}

FolderLock::~FolderLock() {
  if (fd_ < 0) return;
  {
    const std::lock_guard<std::mutex> guard(made_mutex);
    held_locks.erase(folder_);
  }
  if (!created_root_.empty() && std::uncaught_exceptions() > exceptions_) remove_if_left_empty();
  const bool cleared = ftruncate(fd_, 0) == 0;
  static_cast<void>(cleared);
  close(fd_);  // releases the lock
}

}  // namespace talus::workflow
