// The input of a trace reader (internal): a file or standard input, read
// through a sliding buffer, with positioned reads and seeks for files.
#pragma once

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "nodetrace/base/error.hpp"

namespace nodetrace::formats::detail {

// A file or standard input, read through a sliding buffer.
class Input {
 public:
  Input(const std::string& path, const std::string& name) : name_(name) {
    if (path == "-") {
      fd_ = 0;
    } else {
      fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
      if (fd_ < 0) throw base::IoError(fmt::format("{}: cannot open: {}", name_, std::strerror(errno)));
      owned_ = true;
      struct stat info {};
      if (::fstat(fd_, &info) == 0 && S_ISREG(info.st_mode)) {
        seekable_ = true;
        size_ = static_cast<std::uint64_t>(info.st_size);
      } else if (S_ISDIR(info.st_mode)) {
        ::close(fd_);
        throw base::IoError(fmt::format("{}: is a directory", name_));
      }
    }
  }
  ~Input() {
    if (owned_) ::close(fd_);
  }
  Input(const Input&) = delete;
  Input& operator=(const Input&) = delete;

  bool seekable() const { return seekable_; }
  std::uint64_t size() const { return size_; }
  // File offset of the first available byte.
  std::uint64_t offset() const { return offset_; }
  const char* data() const { return buffer_.data() + begin_; }
  std::size_t available() const { return end_ - begin_; }
  bool at_end() { return !ensure(1); }

  // Makes `count` bytes available; false when the input ends first.
  bool ensure(std::size_t count) {
    if (available() >= count) return true;
    if (eof_) return false;
    if (begin_ > 0) {
      std::memmove(buffer_.data(), buffer_.data() + begin_, available());
      end_ -= begin_;
      begin_ = 0;
    }
    // 1 MiB, or less for a smaller file (a whole small file in one read
    // without touching a megabyte of pages).
    const std::size_t least = seekable_ ? static_cast<std::size_t>(std::clamp<std::uint64_t>(size_ + 1, 4096, 1u << 20))
                                        : std::size_t{1} << 20;
    if (buffer_.size() < least) buffer_.resize(least);
    while (end_ < count && !eof_) {
      // Grown as bytes arrive, never to a size only claimed: a damaged
      // length field costs no more memory than the bytes that are there.
      if (end_ == buffer_.size()) buffer_.resize(std::min(count, buffer_.size() * 2));
      std::size_t want = buffer_.size() - end_;
      if (read_limit_ != 0) {  // read ahead no further than the limit unless `count` needs it
        const std::uint64_t position = offset_ + (end_ - begin_);
        const std::uint64_t room = read_limit_ > position ? read_limit_ - position : 0;
        want = static_cast<std::size_t>(std::min<std::uint64_t>(want, std::max<std::uint64_t>(room, count - end_)));
      }
      const ssize_t got = ::read(fd_, buffer_.data() + end_, want);
      if (got < 0) {
        if (errno == EINTR) continue;
        throw base::IoError(fmt::format("{}: read error: {}", name_, std::strerror(errno)));
      }
      if (got == 0) eof_ = true;
      end_ += static_cast<std::size_t>(got);
    }
    return available() >= count;
  }

  // Reads whatever comes next (at least one byte unless at the end).
  std::size_t fill_some() {
    if (!ensure(1)) return 0;
    if (!eof_ && available() < buffer_.size() / 2) ensure(std::min(buffer_.size(), available() + 1));
    return available();
  }

  void consume(std::size_t count) {
    begin_ += count;
    offset_ += count;
  }

  // Moves `count` bytes on, reading none of them that are not already read.
  void skip(std::uint64_t count) {
    if (count <= available()) {
      consume(static_cast<std::size_t>(count));
    } else {
      seek(offset_ + count);
    }
  }

  // Reads ahead stop at file offset `position` (0: no limit), so bytes that
  // will be skipped are not read.
  void limit_reads_to(std::uint64_t position) { read_limit_ = position; }

  // Reads `count` bytes at `position` without disturbing the stream.
  std::string read_at(std::uint64_t position, std::size_t count) const {
    std::string bytes(count, '\0');
    std::size_t done = 0;
    while (done < count) {
      const ssize_t got = ::pread(fd_, bytes.data() + done, count - done, static_cast<off_t>(position + done));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) throw base::IoError(fmt::format("{}: read error at byte {}", name_, position + done));
      done += static_cast<std::size_t>(got);
    }
    return bytes;
  }

  void seek(std::uint64_t position) {
    if (::lseek(fd_, static_cast<off_t>(position), SEEK_SET) < 0) {
      throw base::IoError(fmt::format("{}: cannot seek: {}", name_, std::strerror(errno)));
    }
    begin_ = end_ = 0;
    offset_ = position;
    eof_ = false;
  }

 private:
  std::string name_;
  int fd_ = -1;
  bool owned_ = false;
  bool seekable_ = false;
  std::uint64_t size_ = 0;
  std::vector<char> buffer_;
  std::size_t begin_ = 0, end_ = 0;
  std::uint64_t offset_ = 0;
  std::uint64_t read_limit_ = 0;
  bool eof_ = false;
};

}  // namespace nodetrace::formats::detail
