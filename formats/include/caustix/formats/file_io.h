#pragma once
// Files in and out, with the guarantees the tools promise: reads are bounded,
// and writes are atomic — the output appears complete under its final name or
// not at all (a temporary file in the same directory, fsync, rename).

#include <cstdint>
#include <string>
#include <vector>

#include "caustix/common/status.h"

namespace caustix {

// Reads a whole file. Fails (kInput, naming the path) if it cannot be opened
// or read, or if it is larger than max_bytes.
Result<std::vector<std::uint8_t>> read_file(const std::string& path,
                                            std::uint64_t max_bytes = std::uint64_t{1} << 34);

// Writes bytes to `path` atomically. On failure (kOutput) nothing is left
// behind and an existing file at `path` is untouched.
Status write_file_atomically(const std::string& path, const std::vector<std::uint8_t>& bytes);

// For writers that must open the file themselves (image libraries pick the
// format from the extension): a fresh, empty temporary file next to `path`
// with the same extension. commit() renames it into place; the destructor
// removes it if it was not committed.
class TempFile {
 public:
  static Result<TempFile> create_beside(const std::string& path);
  TempFile(TempFile&& other) noexcept;
  TempFile& operator=(TempFile&&) = delete;
  TempFile(const TempFile&) = delete;
  ~TempFile();
  const std::string& path() const { return temp_; }
  Status commit();

 private:
  TempFile(std::string temp, std::string final_path) : temp_(std::move(temp)), final_(std::move(final_path)) {}
  std::string temp_;
  std::string final_;
  bool done_ = false;
};

}  // namespace caustix
