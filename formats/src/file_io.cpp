#include "caustix/formats/file_io.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

namespace caustix {
namespace {

std::string errno_text() { return std::strerror(errno); }

std::string parent_dir(const std::string& path) {
  const auto parent = std::filesystem::path(path).parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

// Makes the rename durable: without this a crash can lose the new entry.
void sync_dir(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

}  // namespace

Result<std::vector<std::uint8_t>> read_file(const std::string& path, std::uint64_t max_bytes) {
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return make_error(ErrorCode::kInput, path + ": cannot open: " + errno_text());
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return make_error(ErrorCode::kInput, path + ": not a regular file");
  }
  if (static_cast<std::uint64_t>(st.st_size) > max_bytes) {
    ::close(fd);
    return make_error(ErrorCode::kInput, path + ": " + std::to_string(st.st_size) +
                                             " bytes is larger than the limit of " +
                                             std::to_string(max_bytes));
  }
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(st.st_size));
  std::size_t got = 0;
  while (got < bytes.size()) {
    const ssize_t n = ::read(fd, bytes.data() + got, bytes.size() - got);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = n < 0 ? errno_text() : std::string("file shrank while reading");
      ::close(fd);
      return make_error(ErrorCode::kInput, path + ": read failed: " + why);
    }
    got += static_cast<std::size_t>(n);
  }
  ::close(fd);
  return bytes;
}

Result<TempFile> TempFile::create_beside(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string ext = p.extension().string();
  std::string templ = parent_dir(path) + "/." + p.filename().string() + ".tmp.XXXXXX" + ext;
  const int fd = ::mkstemps(templ.data(), static_cast<int>(ext.size()));
  if (fd < 0) {
    return make_error(ErrorCode::kOutput, path + ": cannot create a temporary file in " +
                                              parent_dir(path) + ": " + errno_text());
  }
  // mkstemps creates 0600; give the output the permissions a plain create
  // would (0666 less the umask).
  const mode_t mask = ::umask(0);
  ::umask(mask);
  ::fchmod(fd, 0666 & ~mask);
  ::close(fd);
  return TempFile(templ, path);
}

TempFile::TempFile(TempFile&& o) noexcept
    : temp_(std::move(o.temp_)), final_(std::move(o.final_)), done_(o.done_) {
  o.done_ = true;
}

TempFile::~TempFile() {
  if (!done_) ::unlink(temp_.c_str());
}

Status TempFile::commit() {
  // Flush the data before the rename so the name never points at a file
  // whose contents are still in flight.
  const int fd = ::open(temp_.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (::rename(temp_.c_str(), final_.c_str()) != 0) {
    return make_error(ErrorCode::kOutput, final_ + ": cannot move the finished file into place: " + errno_text());
  }
  done_ = true;
  sync_dir(parent_dir(final_));
  return Status::success();
}

Status write_file_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  auto temp = TempFile::create_beside(path);
  if (!temp) return temp.error();
  const int fd = ::open(temp->path().c_str(), O_WRONLY | O_TRUNC);
  if (fd < 0) return make_error(ErrorCode::kOutput, temp->path() + ": cannot open: " + errno_text());
  std::size_t put = 0;
  while (put < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + put, bytes.size() - put);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string why = errno_text();
      ::close(fd);
      return make_error(ErrorCode::kOutput, path + ": write failed: " + why);
    }
    put += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0 || ::close(fd) != 0) {
    return make_error(ErrorCode::kOutput, path + ": write failed: " + errno_text());
  }
  return temp->commit();
}

}  // namespace caustix
