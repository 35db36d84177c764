#pragma once
// One writer per results folder: a lock (flock) on the hidden file .<name>.lock
// beside the folder, held while a run or a study writes it, so a second
// needlesim aimed at the same folder is refused before it touches anything.
#include <filesystem>
#include <string>

#include "needlesim/core/error.hpp"

namespace needlesim::io {

class FolderLock {
 public:
  enum class Mode { Exclusive, Shared };  // Shared: the ranks of one MPI study
  // InputError naming `field` at `where` when another process holds the lock
  // (Exclusive: any holder; Shared: an exclusive holder); Error when the lock
  // file cannot be made. The parent folder of `folder` must exist.
  FolderLock(const std::filesystem::path& folder, const std::string& field, const SourceLocation& where,
             Mode mode = Mode::Exclusive);
  ~FolderLock();
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

  // The lock file of `folder`: .<name>.lock in its parent.
  static std::filesystem::path lockFileOf(const std::filesystem::path& folder);

 private:
  std::filesystem::path file_;
  int fd_ = -1;
};

}  // namespace needlesim::io
