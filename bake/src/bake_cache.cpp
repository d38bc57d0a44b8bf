#include "caustix/bake/bake_cache.h"

#include <xxhash.h>

#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>

#include "caustix/bake/presets.h"
#include "caustix/common/version.h"
#include "caustix/formats/file_io.h"

namespace caustix::bake {
namespace fs = std::filesystem;
namespace {

// Changes whenever what an entry holds, or how its key is made, changes.
constexpr const char* kCacheFormat = "caustix-bake-cache 1";

std::string hex(const XXH128_hash_t& h) {
  char s[33];
  std::snprintf(s, sizeof s, "%016llx%016llx", static_cast<unsigned long long>(h.high64),
                static_cast<unsigned long long>(h.low64));
  return s;
}

// Hashes the file's bytes into `state`, a megabyte at a time. False when
// it cannot be read.
bool hash_file(const std::string& path, XXH3_state_t* state) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::vector<char> buffer(std::size_t{1} << 20);
  while (in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    if (in.gcount() > 0) XXH3_128bits_update(state, buffer.data(), static_cast<std::size_t>(in.gcount()));
  }
  return in.eof();
}

struct State {
  XXH3_state_t* s = XXH3_createState();
  State() { XXH3_128bits_reset(s); }
  ~State() { XXH3_freeState(s); }
  State(const State&) = delete;
  State& operator=(const State&) = delete;
  void add(const std::string& text) { XXH3_128bits_update(s, text.data(), text.size() + 1); }  // with its NUL
  std::string digest() const { return hex(XXH3_128bits_digest(s)); }
};

// "" when the file cannot be read.
std::string file_hash(const std::string& path) {
  State st;
  return hash_file(path, st.s) ? st.digest() : std::string();
}

std::string one_line(std::string s) {
  for (char& c : s) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return s;
}

// The manifest: the format line, then "input HASH PATH" per file read and
// "warning TEXT" per warning. Reused when every input hashes the same.
std::optional<std::vector<std::string>> read_manifest(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line) || line != kCacheFormat) return std::nullopt;
  std::vector<std::string> warnings;
  bool any_input = false;
  while (std::getline(in, line)) {
    if (line.rfind("input ", 0) == 0 && line.size() > 6 + 32 + 1) {
      const std::string hash = line.substr(6, 32), file = line.substr(6 + 33);
      if (file_hash(file) != hash) return std::nullopt;
      any_input = true;
    } else if (line.rfind("warning ", 0) == 0) {
      warnings.push_back(line.substr(8));
    } else if (line != "end") {
      return std::nullopt;
    } else {
      return any_input ? std::optional(warnings) : std::nullopt;  // complete
    }
  }
  return std::nullopt;  // truncated: no "end"
}

}  // namespace

std::string default_cache_dir() {
  if (const char* d = std::getenv("CAUSTIX_CACHE_DIR"); d && *d) return d;
  if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return (fs::path(d) / "caustix").string();
  if (const char* d = std::getenv("HOME"); d && *d) return (fs::path(d) / ".cache" / "caustix").string();
  std::error_code ec;
  const fs::path tmp = fs::temp_directory_path(ec);
  return ((ec ? fs::path("/tmp") : tmp) / ("caustix-cache-" + std::to_string(getuid()))).string();
}

bool is_baked_path(const std::string& path) {
  std::string ext = fs::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".cxb";
}

Result<CachedBake> bake_cached(const std::string& scene_path, const CacheRequest& request, const BakeObserver& observer) {
  BakeOptions options;
  if (!request.preset.empty()) {
    const Preset* p = find_preset(request.preset);
    if (!p) return make_error(ErrorCode::kUsage, "unknown bake preset '" + request.preset + "' (fast, balanced or accurate)");
    apply_preset(*p, options);
  }
  options.default_light = request.default_light;
  options.observer = observer;

  // The key: what the bytes depend on besides the files read.
  State key;
  key.add(kCacheFormat);
  key.add(kVersionString);
  key.add(request.preset);
  key.add(request.default_light ? "default light" : "no default light");
  if (!hash_file(scene_path, key.s)) {
    return make_error(ErrorCode::kInput, scene_path + ": cannot read: " + std::string(std::strerror(errno)));
  }
  const std::string dir = request.dir.empty() ? default_cache_dir() : request.dir;
  const fs::path stem = fs::path(dir) / key.digest();
  CachedBake out;
  out.cxb_path = stem.string() + ".cxb";
  const std::string manifest = stem.string() + ".manifest";
  std::error_code ec;
  if (fs::exists(out.cxb_path, ec)) {
    if (auto warnings = read_manifest(manifest)) {
      out.reused = true;
      out.warnings = std::move(*warnings);
      return out;
    }
  }

  auto baked = bake_scene(scene_path, options);
  if (!baked) return baked.error();
  fs::create_directories(dir, ec);
  if (ec) {
    return make_error(ErrorCode::kOutput, "cannot make the bake cache directory '" + dir + "': " + ec.message() +
                                              " (choose another with --cache DIR or CAUSTIX_CACHE_DIR)");
  }
  std::string text = std::string(kCacheFormat) + "\n";
  for (const std::string& input : baked->inputs) {
    const std::string absolute = fs::absolute(input, ec).lexically_normal().string();
    const std::string hash = file_hash(absolute);
    // Gone since the bake read it: what was baked cannot be checked later.
    if (hash.empty()) return make_error(ErrorCode::kInput, input + ": cannot read it again to note it in the bake cache");
    text += "input " + hash + " " + absolute + "\n";
  }
  for (const std::string& w : baked->warnings) text += "warning " + one_line(w) + "\n";
  text += "end\n";
  if (Status st = write_file_atomically(out.cxb_path, baked->cxb); !st) return st.error();
  if (Status st = write_file_atomically(manifest, std::vector<std::uint8_t>(text.begin(), text.end())); !st) return st.error();
  out.warnings = std::move(baked->warnings);
  return out;
}

}  // namespace caustix::bake
