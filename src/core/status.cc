#include "gyrocomp/core/status.h"

namespace gyrocomp {

const char* ErrorKindName(ErrorKind kind) {
  switch (kind) {
    case ErrorKind::kInvalidInput: return "invalid input";
    case ErrorKind::kInvalidArgument: return "invalid argument";
    case ErrorKind::kIo: return "i/o error";
    case ErrorKind::kDidNotConverge: return "did not converge";
    case ErrorKind::kUnsupported: return "unsupported";
    case ErrorKind::kInternal: return "internal error";
  }
  return "unknown error";
}

}  // namespace gyrocomp
