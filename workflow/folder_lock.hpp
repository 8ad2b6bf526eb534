// One writer per output folder: every stage that writes into a folder (mesh, solve, post, run,
// fos) first takes an exclusive flock on FOLDER/.talus.lock and holds it until it ends. A second
// talus aimed at the same folder stops at once, before it touches a file, with a message naming
// the holder's pid and command line (written into the lock file by the holder).
#pragma once
#include <string>

namespace talus::workflow {

class FolderLock {
 public:
  // Takes the lock of `folder` (which exists), or throws talus::Error naming the holder.
  explicit FolderLock(const std::string& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

}  // namespace talus::workflow
