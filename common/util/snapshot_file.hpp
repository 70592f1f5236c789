#pragma once
/// @file A file that is rewritten as a whole, often (a program's status, twice a second), and that
/// a reader always sees whole: the last complete snapshot, never half of one.

#include <string>
#include <string_view>
#include <utility>

namespace tb {

/// Writes PATH by filling PATH.tmp and swapping the two names with renameat2(RENAME_EXCHANGE).
///
/// Why not write PATH.tmp and rename() it over PATH each time: on ext4 a rename over an existing
/// file starts the new file's writeback at once (the auto_da_alloc heuristic). That made a 20 KB
/// status file cost ~230 µs a write against ~27 µs exchanged (measured 2026-11-27 on this VM's
/// disk), the largest single cost of a full station at 49 neighbours (docs/latency.md). The two
/// inodes stay open and are overwritten in turn with pwrite + ftruncate, never truncated to zero
/// (which triggers the same heuristic at close).
///
/// A reader that opened PATH keeps a whole snapshot until the write after next overwrites its
/// inode (one write period later). On a file system without RENAME_EXCHANGE (EINVAL) the
/// writer falls back to write-and-rename for good. PATH.tmp (the previous snapshot) is removed
/// when the writer is destroyed.
class SnapshotFile {
 public:
  explicit SnapshotFile(std::string path);
  ~SnapshotFile();
  SnapshotFile(const SnapshotFile&) = delete;
  SnapshotFile& operator=(const SnapshotFile&) = delete;

  /// Replaces the file's content with @p content. Throws std::system_error naming the file and
  /// the step that failed; the next write starts afresh.
  void write(std::string_view content);

  const std::string& path() const { return path_; }

 private:
  void reset();

  std::string path_;
  std::string tmp_;
  int current_ = -1;  // the inode named path_
  int spare_ = -1;    // the inode named tmp_, the next to be written
  bool exchange_ = true;
};

/// A status file that a program rewrites periodically and must not stop for: a write that fails
/// is logged when writes start failing and again when they work again, not at every period.
class StatusFileWriter {
 public:
  explicit StatusFileWriter(std::string path) : file_(std::move(path)) {}
  void write(std::string_view content);

 private:
  SnapshotFile file_;
  bool failing_ = false;
};

}  // namespace tb
