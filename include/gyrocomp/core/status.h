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

// "invalid input" | "invalid argument" | "i/o error" | "did not converge" | "unsupported" |
// "internal error".
const char* ErrorKindName(ErrorKind kind);

// What went wrong: a kind for the caller's decisions and a message for the user.
struct Error {
  ErrorKind kind = ErrorKind::kInternal;  // default kInternal
  std::string message;                    // names the field, or file:line:col, at fault
};

// Error of kind kInvalidInput with `message`.
inline Error InvalidInput(std::string message) { return {ErrorKind::kInvalidInput, std::move(message)}; }
// Error of kind kInvalidArgument with `message`.
inline Error InvalidArgument(std::string message) { return {ErrorKind::kInvalidArgument, std::move(message)}; }
// Error of kind kIo with `message`.
inline Error IoError(std::string message) { return {ErrorKind::kIo, std::move(message)}; }
// Error of kind kUnsupported with `message`.
inline Error Unsupported(std::string message) { return {ErrorKind::kUnsupported, std::move(message)}; }
// Error of kind kInternal with `message`.
inline Error InternalError(std::string message) { return {ErrorKind::kInternal, std::move(message)}; }

// Result<T>: either a T or an Error (a small stand-in for C++23 std::expected).
template <class T>
class [[nodiscard]] Result {
 public:
  // A success holding `value`.
  Result(T value) : v_(std::move(value)) {}          // NOLINT: implicit by design
  // A failure holding `error`.
  Result(Error error) : v_(std::move(error)) {}      // NOLINT: implicit by design
  // True when a value is held.
  bool ok() const { return v_.index() == 0; }
  // Same as ok().
  explicit operator bool() const { return ok(); }
  // The value; only when ok() (asserted).
  T& value() & { assert(ok()); return std::get<0>(v_); }
  // The value; only when ok() (asserted).
  const T& value() const& { assert(ok()); return std::get<0>(v_); }
  // The value moved out; only when ok() (asserted).
  T&& value() && { assert(ok()); return std::get<0>(std::move(v_)); }
  // value().
  T& operator*() & { return value(); }
  // value().
  const T& operator*() const& { return value(); }
  // &value().
  T* operator->() { return &value(); }
  // &value().
  const T* operator->() const { return &value(); }
  // The error; only when !ok() (asserted).
  const Error& error() const { assert(!ok()); return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

// Status: success or an Error, for operations without a value.
class [[nodiscard]] Status {
 public:
  Status() = default;
  // A failure holding `error`.
  Status(Error error) : error_(std::move(error)), ok_(false) {}  // NOLINT: implicit by design
  // Success (the same as a default-constructed Status).
  static Status Ok() { return Status(); }
  // True on success.
  bool ok() const { return ok_; }
  // Same as ok().
  explicit operator bool() const { return ok_; }
  // The error; only when !ok() (asserted).
  const Error& error() const { assert(!ok_); return error_; }

 private:
  Error error_;
  bool ok_ = true;
};

}  // namespace gyrocomp
