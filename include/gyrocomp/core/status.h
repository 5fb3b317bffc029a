// Errors returned to callers. The library never calls exit() and never aborts on bad user input:
// it returns an Error whose message names the field, or the file, line and column, at fault.
// Programmer errors (violated preconditions inside the library) are assertions instead.
#pragma once

#include <cassert>
#include <string>
#include <utility>
#include <variant>

namespace gyrocomp {

// The short list of error kinds. The CLI maps kInvalidInput, kInvalidArgument, kUnsupported and
// kIo (a file the user named cannot be opened or created) to exit status 2, the rest to 1.
enum class ErrorKind {
  kInvalidInput,     // malformed data: a file, a cell, a timestamp (message: file:line:col: what)
  kInvalidArgument,  // an option out of range ("VmdOptions::alpha = -1: must be > 0")
  kIo,               // cannot open / read / write a file
  kDidNotConverge,   // an iterative method stopped before its criterion
  kUnsupported,      // valid but not handled (e.g. a model file from another schema version)
  kInternal,         // a bug or a failure in a dependency
};

const char* ErrorKindName(ErrorKind kind);

struct Error {
  ErrorKind kind = ErrorKind::kInternal;
  std::string message;
};

inline Error InvalidInput(std::string message) { return {ErrorKind::kInvalidInput, std::move(message)}; }
inline Error InvalidArgument(std::string message) { return {ErrorKind::kInvalidArgument, std::move(message)}; }
inline Error IoError(std::string message) { return {ErrorKind::kIo, std::move(message)}; }
inline Error Unsupported(std::string message) { return {ErrorKind::kUnsupported, std::move(message)}; }
inline Error InternalError(std::string message) { return {ErrorKind::kInternal, std::move(message)}; }

// Result<T>: either a T or an Error (a small stand-in for C++23 std::expected).
template <class T>
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

// Status: success or an Error, for operations without a value.
class [[nodiscard]] Status {
 public:
  Status() = default;
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT: implicit by design
  static Status Ok() { return Status(); }
  bool ok() const { return ok_; }
  explicit operator bool() const { return ok_; }
  const Error& error() const { assert(!ok_); return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace gyrocomp
