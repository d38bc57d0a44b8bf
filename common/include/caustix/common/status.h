#pragma once
// Errors are values: every fallible caustix function returns Result<T> (or
// Status for Result<void>). An Error carries a code (which maps onto a CLI
// exit code) and a message that names the place: file, JSON line and column,
// chunk tag and offset, or vertex index. No exceptions cross a public API.

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace caustix {

// Broad classes of failure. Each maps to one documented exit code
// (exit_codes.h); never renumber, tools and scripts depend on them.
enum class ErrorCode : int {
  kInternal = 1,     // a bug or an unexpected library failure
  kUsage = 2,        // bad command line
  kInput = 3,        // scene.json or a mesh is missing or invalid
  kContainer = 4,    // a .cxb file is malformed, corrupt or unsupported
  kOutput = 5,       // the output could not be written
  kGraphics = 6,     // no usable OpenGL context, or a GL failure
  kBudget = 7,       // stopped by a --max-seconds or --max-memory budget
};

struct Error {
  ErrorCode code = ErrorCode::kInternal;
  std::string message;
};

inline Error make_error(ErrorCode code, std::string message) {
  return Error{code, std::move(message)};
}

template <typename T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}          // NOLINT: implicit by design
  Result(Error error) : v_(std::move(error)) {}      // NOLINT: implicit by design

  bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }

  T& value() & { assert(ok()); return std::get<0>(v_); }
  const T& value() const& { assert(ok()); return std::get<0>(v_); }
  T&& value() && { assert(ok()); return std::get<0>(std::move(v_)); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }

  const Error& error() const { assert(!ok()); return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

struct Ok {};

// Status is Result<Ok>: success carries nothing.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT
  static Status success() { return Status(); }
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { assert(!ok_); return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace caustix

// Return early with the error of a failed Status / Result expression.
#define CAUSTIX_RETURN_IF_ERROR(expr)                 \
  do {                                                \
    auto&& caustix_status_ = (expr);                  \
    if (!caustix_status_.ok()) return caustix_status_.error(); \
  } while (0)

// Assigns the value of a Result expression to `lhs` (an lvalue declared
// before), or returns its error: CAUSTIX_ASSIGN_OR_RETURN(mesh, load(path));
#define CAUSTIX_ASSIGN_OR_RETURN(lhs, expr)            \
  do {                                                 \
    auto caustix_result_ = (expr);                     \
    if (!caustix_result_.ok()) return caustix_result_.error(); \
    lhs = std::move(*caustix_result_);                 \
  } while (0)
