// Atomic CSV / text writing (include/gyrocomp/io/io.h): a one-file OutputSet
// (include/gyrocomp/io/output.h), so a single write gets the same care as a command's set of
// outputs: symbolic links followed and their target replaced, FIFOs and devices written through,
// write errors returned, no temporary left behind, no non-finite number written.
#include "gyrocomp/io/io.h"

#include <string>

#include "gyrocomp/io/output.h"

namespace gyrocomp {

Status WriteCsvAtomic(const std::string& path, const Table& table) {
  OutputSet out;
  if (Status s = out.StageCsv(path, table); !s) return s;
  return out.Commit();
}

Status WriteTextAtomic(const std::string& path, const std::string& text) {
  OutputSet out;
  if (Status s = out.StageText(path, text); !s) return s;
  return out.Commit();
}

}  // namespace gyrocomp
