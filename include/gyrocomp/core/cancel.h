// A cancellation request shared between a caller and a long computation (minimal, issue 14; to be
// merged with issue 15's mechanism when that lands). The library installs no signal handlers: the
// owner of the process (the CLI's main, a Python interpreter) decides what sets the flag.
//
// Some long calls poll a token themselves (issue 24): VmdOptions::cancel (before every update),
// CuckooSearchOptions::cancel (before every evaluation: no new parameter set starts, the running
// ones finish) and AllanOptions::cancel (before every tau); they throw Cancelled on the calling
// thread. Elsewhere callers poll it in the progress hooks they install (VmdOptions::on_iteration,
// CuckooSearchOptions::on_generation, the pipeline's ProgressCallback) and leave the call by
// throwing Cancelled from the hook. Not polled yet: inside sample entropy counting and inside
// one LIBSVM fit. Those hooks run on
// the calling thread between rounds of work, and the code around them releases everything by
// RAII (worker pools join in their destructors), so unwinding from them is safe.
#pragma once

#include <atomic>
#include <exception>

namespace gyrocomp {

class CancellationToken {
 public:
  void Cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  void Reset() { cancelled_.store(false, std::memory_order_relaxed); }
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> cancelled_{false};
};

// Thrown by a caller's progress hook when its token was cancelled (see above).
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

}  // namespace gyrocomp
