#include "common/util/snapshot_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <system_error>
#include <utility>

#include <spdlog/spdlog.h>

namespace tb {
namespace {

[[noreturn]] void fail(const std::string& what, const std::string& file, int err) {
  throw std::system_error(err, std::generic_category(), what + " " + file);
}

void close_fd(int& fd) {
  if (fd >= 0)
    ::close(fd);
  fd = -1;
}

}  // namespace

SnapshotFile::SnapshotFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {}

SnapshotFile::~SnapshotFile() {
  if (spare_ >= 0)
    ::unlink(tmp_.c_str());
  close_fd(spare_);
  close_fd(current_);
}

void SnapshotFile::reset() {
  close_fd(spare_);
  close_fd(current_);
}

void SnapshotFile::write(std::string_view content) {
  if (spare_ < 0) {
    spare_ = ::open(tmp_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (spare_ < 0)
      fail("cannot open", tmp_, errno);
  }
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n =
        ::pwrite(spare_, content.data() + done, content.size() - done, static_cast<off_t>(done));
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : EIO;
      reset();
      fail("cannot write", tmp_, err);
    }
    done += static_cast<std::size_t>(n);
  }
  if (::ftruncate(spare_, static_cast<off_t>(content.size())) != 0) {
    const int err = errno;
    reset();
    fail("cannot truncate", tmp_, err);
  }
  if (current_ >= 0 && exchange_) {
    if (::renameat2(AT_FDCWD, tmp_.c_str(), AT_FDCWD, path_.c_str(), RENAME_EXCHANGE) == 0) {
      std::swap(current_, spare_);
      return;
    }
    const int err = errno;
    if (err == EINVAL) {
      exchange_ = false;  // not on this file system: rename below, from now on
    } else {
      // ENOENT and the like: somebody moved our files; start again from nothing next time.
      reset();
      fail("cannot exchange " + tmp_ + " with", path_, err);
    }
  }
  if (::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    reset();
    fail("cannot rename " + tmp_ + " to", path_, err);
  }
  close_fd(current_);
  current_ = std::exchange(spare_, -1);
  if (!exchange_)
    close_fd(current_);  // write-and-rename needs no second inode kept open
}

void StatusFileWriter::write(std::string_view content) {
  try {
    file_.write(content);
    if (std::exchange(failing_, false))
      spdlog::info("status file {} written again", file_.path());
  } catch (const std::system_error& e) {
    if (!std::exchange(failing_, true))
      spdlog::error("status file: {}", e.what());
  }
}

}  // namespace tb
