// Helpers shared by the binding files: numpy <-> span / vector without copies, keyword arguments
// onto Options structs (defaults stay the library's), library errors -> Python exceptions, and
// the progress / cancellation hook of the long calls.
#pragma once

#include <cstdint>
#include <exception>
#include <functional>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "gyrocomp/core/cancel.h"
#include "gyrocomp/core/status.h"

namespace gyrocomp::python {

namespace py = pybind11;

// A 1-D float64 array; other dtypes / strides are converted once by numpy (forcecast), a
// contiguous float64 array is used in place.
using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;

// The array's data as a span (no copy). ValueError when it is not 1-D.
std::span<const double> AsSpan(const DoubleArray& a, const char* name);

// A numpy array that takes over the vector's buffer (no copy).
py::array_t<double> ToNumpy(std::vector<double>&& v);
py::array_t<std::int64_t> ToNumpy(std::vector<std::int64_t>&& v);
// Rows of equal length as one 2-D array (one copy: the rows are separate buffers).
py::array_t<double> ToNumpy2d(const std::vector<std::vector<double>>& rows);

// Raises the library's error: ValueError for bad input / arguments / unsupported content,
// RuntimeError for I/O, did-not-converge and internal errors. The message is the library's.
[[noreturn]] void Raise(const Error& error);

template <class T>
T Unwrap(Result<T>&& r) {
  if (!r.ok()) Raise(r.error());
  return std::move(r).value();
}
inline void Check(const Status& s) {
  if (!s.ok()) Raise(s.error());
}

// Keyword arguments onto an Options struct: Get() only overwrites a field that was passed, so the
// defaults are the struct's own; Done() raises TypeError naming any keyword nobody read.
class Kwargs {
 public:
  Kwargs(py::dict kwargs, std::string function) : kw_(std::move(kwargs)), fn_(std::move(function)) {}
  template <class T>
  void Get(const char* name, T* field) {
    if (!kw_.contains(name)) return;
    used_.insert(name);
    try {
      *field = kw_[name].template cast<T>();
    } catch (const py::cast_error&) {
      throw py::type_error(fn_ + "(): keyword '" + name + "' has the wrong type (" +
                           std::string(py::str(py::type::of(kw_[name]))) + ")");
    }
  }
  // A named choice (an enum, a tau grid) parsed from its text by parse(text) -> std::optional;
  // ValueError "function(): name=text: <what>" when parse refuses it.
  template <class T, class Parse>
  void GetParsed(const char* name, T* field, Parse parse, const std::string& what) {
    py::object v = Take(name);
    if (v.is_none()) return;
    const std::string text = py::str(v);
    const std::optional<T> parsed = parse(text);
    if (!parsed) throw py::value_error(fn_ + "(): " + name + "=" + text + ": " + what);
    *field = *parsed;
  }
  // The raw value (None when absent), marked as read.
  py::object Take(const char* name);
  // A nested options dict (e.g. noise={...}); empty when absent.
  py::dict Nested(const char* name);
  void Done() const;
  const std::string& function() const { return fn_; }

 private:
  py::dict kw_;
  std::string fn_;
  std::set<std::string> used_;
};

// Reads a whole keyword dict with read(Kwargs&) and raises TypeError for any keyword it left:
// ReadAll(kw.Nested("vmd"), "run_parallel_model(vmd=...)", ReadVmdOptions).
template <class Read>
auto ReadAll(py::dict kwargs, std::string function, Read&& read) {
  Kwargs kw(std::move(kwargs), std::move(function));
  auto out = read(kw);
  kw.Done();
  return out;
}

// progress(stage: str, fraction: float) and the token of a LongCall, polled from the library's
// hooks on the LongCall's worker thread. Poll(): raises Cancelled when the token is set, then
// calls the progress callable (with the GIL).
class Hooks {
 public:
  Hooks(py::object progress, const CancellationToken* token) : progress_(std::move(progress)), token_(token) {}
  void Poll(const std::string& stage, double fraction) const;

 private:
  py::object progress_;
  const CancellationToken* token_;
};

// A long call that Ctrl-C, the caller's CancellationToken or a Dask cancel (gyrocomp.dask) can
// stop. Run(fn) runs fn on a worker thread with the GIL released; the calling thread
// waits in steps of kPollInterval and at each step (1) copies the caller's token into token(),
// (2) takes the GIL and runs Python's signal handlers (PyErr_CheckSignals: Ctrl-C raises
// KeyboardInterrupt; they run only on the main thread, elsewhere this is a no-op) and, when one
// raised, sets token(). The library polls token() inside its loops (VmdOptions::cancel,
// SampleEntropyOptions::cancel, CuckooSearchOptions::cancel, AllanOptions::cancel, and the hooks),
// so the worker returns (by Cancelled) within the library's polling interval and is joined; then
// the signal handler's exception (KeyboardInterrupt) is raised, else gyrocomp.Cancelled when the
// caller's token stopped it, else fn's result or exception. Nothing outlives the call: the worker
// is always joined, and the library writes no file.
class LongCall {
 public:
  static constexpr int kPollIntervalMs = 20;
  explicit LongCall(const CancellationToken* caller) : caller_(caller) {}
  LongCall(const LongCall&) = delete;
  LongCall& operator=(const LongCall&) = delete;
  // The token to put into the library's options.
  const CancellationToken* token() const { return &stop_; }

  template <class F>
  auto Run(F&& fn) {
    std::optional<decltype(fn())> out;
    std::exception_ptr error;
    Wait([&] {
      try {
        out.emplace(fn());
      } catch (...) {
        error = std::current_exception();
      }
    });
    if (error) std::rethrow_exception(error);
    return std::move(*out);
  }

 private:
  // Runs work (which never throws) on a worker thread and waits as above; raises the signal
  // handler's exception (py::error_already_set) after the join.
  void Wait(const std::function<void()>& work);

  CancellationToken stop_;
  const CancellationToken* caller_;
};

// Runs fn with the GIL released (short calls, no cancellation).
template <class F>
auto WithoutGil(F&& fn) {
  py::gil_scoped_release release;
  return fn();
}

}  // namespace gyrocomp::python
