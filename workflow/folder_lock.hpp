// One writer per output folder: every stage that writes into a folder (mesh, solve, post, run,
// fos) first takes an exclusive flock on FOLDER/.talus.lock and holds it until it ends. A second
// talus aimed at the same folder stops at once, before it touches a file, with a message naming
// the holder's pid and command line (written into the lock file by the holder).
//
// A failed stage leaves no empty folder behind: a folder that create_output_folder made for this
// process, and that holds nothing but the lock file when its FolderLock is left by an exception,
// is removed with the lock file and the parents that were made for it.
#pragma once
#include <string>

namespace talus::workflow {

// Creates `folder` and its missing parents, and remembers which of them it made; throws
// talus::Error naming the folder when it cannot be one (a file, /dev/null, an empty name).
void create_output_folder(const std::string& folder);

class FolderLock {
 public:
  // Takes the lock of `folder` (which exists), or throws talus::Error naming the holder.
  explicit FolderLock(const std::string& folder);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  // The descriptor of the lock this process holds on `folder` (the name it was taken by), -1
  // when it holds none: a `--ranks` driver hands it to its ranks (workflow/ranks_link.hpp).
  static int held_descriptor(const std::string& folder);

  // For a process that ends without unwinding (std::terminate: out of memory inside an OpenMP
  // region): what the destructors of the locks it holds would do on an exception, that is,
  // remove the folders made for it that hold nothing but the lock file.
  static void release_all_after_fatal_error();

 private:
  void remove_if_left_empty();

  int fd_ = -1;
  std::string folder_;
  std::string created_root_;   // the outermost folder made for this one; empty if it existed
  int exceptions_ = 0;         // std::uncaught_exceptions() when the lock was taken
};

}  // namespace talus::workflow
