// A cancellation request shared between a caller and a long computation. The library installs no
// signal handlers: the owner of the process (the CLI's main, a Python interpreter) decides what
// sets the flag.
//
// Some long calls poll a token themselves (latencies: docs/explanation/performance.md, "Cancellation"):
// VmdOptions::cancel (before every update), SampleEntropyOptions::cancel (inside the pair counting,
// every counting thread), SvrOptions::cancel (inside LIBSVM's solver, from its print hook; svr.cc),
// CuckooSearchOptions::cancel (before every evaluation, and passed to every SVR fit of the search
// and the refit) and AllanOptions::cancel (before every tau); they throw Cancelled on the calling
// thread (worker threads pass it there). Elsewhere callers poll it in the progress hooks they
// install (VmdOptions::on_iteration, CuckooSearchOptions::on_generation, the pipeline's
// ProgressCallback) and leave the call by throwing Cancelled from the hook. DriftFitOptions::cancel
// is polled between the steps of a drift fit (each candidate, lag tau, feature build, model fit,
// band). The CLI does not need the token: its signal handler removes the temporaries and exits
// (tools/main.cc). Python sets it from a waiting loop (python/src/convert.h, LongCall). Those hooks
// run on the calling thread between rounds of work, and the code around them releases everything by
// RAII (worker pools join in their destructors), so unwinding from them is safe.
#pragma once

#include <atomic>
#include <exception>

namespace gyrocomp {

// A flag set by the caller (any thread) and polled by a long computation; never cleared by the
// library. Not copyable (it holds a std::atomic): pass a pointer.
class CancellationToken {
 public:
  // Requests cancellation; the computation stops at its next poll. Safe from any thread.
  void Cancel() { cancelled_.store(true, std::memory_order_relaxed); }
  // Clears the request, so the token can be reused for another call.
  void Reset() { cancelled_.store(false, std::memory_order_relaxed); }
  // True once Cancel() was called (and Reset() not since).
  bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

 private:
  std::atomic<bool> cancelled_{false};
};

// Thrown by a caller's progress hook when its token was cancelled (see above).
struct Cancelled : std::exception {
  // "cancelled".
  const char* what() const noexcept override { return "cancelled"; }
};

// The poll of a long computation's options token: throws Cancelled once `token` (may be null)
// was cancelled.
inline void ThrowIfCancelled(const CancellationToken* token) {
  if (token != nullptr && token->cancelled()) throw Cancelled();
}

}  // namespace gyrocomp
