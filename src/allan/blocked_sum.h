// Private helper of the allan stage (not installed).
#pragma once

namespace gyrocomp::allan_internal {

// Sum of a long series of squares with bounded rounding error: block partial sums (the error
// grows with the block count, not with N), close to numpy's pairwise summation.
class BlockedSum {
 public:
  void Add(double v) {
    block_ += v;
    if (++count_ == 1024) Flush();
  }
  double Total() {
    Flush();
    return total_;
  }

 private:
  void Flush() {
    total_ += block_;
    block_ = 0.0;
    count_ = 0;
  }
  double total_ = 0.0, block_ = 0.0;
  int count_ = 0;
};

}  // namespace gyrocomp::allan_internal
