// Writing output files without ever losing a user's data: one transaction for all the files a
// command writes.
//
//     OutputSet out;
//     out.AddInput("run.csv");                       // never written, whatever the path spelling
//     if (Status s = out.Declare("adev.csv"); !s) ...  // before any work: refuses '' , an input,
//     if (Status s = out.Declare("summary.json"); !s) ...  // a missing or read-only folder
//     ... long computation ...
//     out.StageCsv("adev.csv", table);               // content goes to temporaries
//     out.StageText("summary.json", text);
//     if (Status s = out.Commit(); !s) ...           // fsync + rename all, then write-through
//
// What a destination is decides how it is written:
//   - a regular file or a new name: a temporary file in the same folder ("." + name + ".tmp" +
//     pid + "_" + random), renamed over the target only at Commit, keeping the target's mode;
//   - a symbolic link: followed to its target, and the target is replaced atomically (the link
//     stays a link);
//   - a FIFO, a character device (/dev/null, a terminal), anything under /dev/ or /proc/ (so
//     /dev/stdout), and "-" (stdout): buffered in memory and written through after the renames,
//     never replaced (renaming over a device node would replace it for the whole machine);
//   - a directory, a block device or a socket: refused.
// A destination that is the same file as an input (same device and inode: across symbolic and
// hard links), or the same file as another destination, is refused at Declare. Write errors at
// Commit (ENOSPC on /dev/full) are returned, never swallowed. Destroying a set that was not
// committed removes its temporaries. A ".gz" destination is gzip-compressed.
//
// Numbers: StageCsv refuses a table holding a NaN or an infinity (the message names the column and
// the line), so a non-finite number never reaches a file with success.
//
// Signals: every live temporary is also listed in a process-wide table that
// RemoveLiveTemporaryFiles() reads without allocating or locking, so a program's SIGINT / SIGTERM
// handler can remove them. The library installs no signal handler.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "gyrocomp/core/status.h"
#include "gyrocomp/io/io.h"

namespace gyrocomp {

// A command's output files, written all or none: each is staged in a temporary beside its target
// and renamed over it on Commit().
class OutputSet {
 public:
  OutputSet();
  ~OutputSet();  // removes the temporaries unless Commit() succeeded
  OutputSet(const OutputSet&) = delete;
  OutputSet& operator=(const OutputSet&) = delete;

  // Registers a file that must never be written. "-" (stdin) and paths that cannot be stat'ed are
  // ignored (reading them reports the problem). Call before Declare.
  void AddInput(const std::string& path);

  // Checks `path` as a destination and, for a file to be replaced, creates its temporary (which
  // proves the folder exists and is writable). Errors (kInvalidArgument or kIo, exit 2 in the
  // CLI): empty name, a directory, the same file as an input or as another destination, a
  // missing or read-only folder.
  Status Declare(const std::string& path);

  // Whether `path` was declared.
  bool IsDeclared(const std::string& path) const;

  // Writes the content of a declared destination (declares it first when it was not). Each
  // destination takes exactly one Stage call.
  Status StageCsv(const std::string& path, const Table& table);
  // The same with text content.
  Status StageText(const std::string& path, std::string_view text);

  // fsync's and renames every staged temporary over its target, then writes the buffered
  // destinations (FIFOs, devices, stdout). A declared destination that was never staged is not
  // created. Errors are kIo; renames already done stay done (each one is atomic on its own).
  Status Commit();

  // Removes every temporary now (what the destructor does).
  void Discard();

 private:
  struct Entry;
  Entry* Find(const std::string& path);
  const Entry* Find(const std::string& path) const;
  Result<Entry*> FindOrDeclare(const std::string& path);
  Status CheckNotInput(const Entry& e) const;

  struct InputId {
    std::string path;
    unsigned long long dev = 0;
    unsigned long long ino = 0;
  };
  std::vector<InputId> inputs_;
  std::vector<std::unique_ptr<Entry>> entries_;
};

// Unlinks every temporary file of every live OutputSet of this process. Async-signal-safe (reads
// a fixed table of lock-free slots, calls only unlink): meant for a program's SIGINT / SIGTERM
// handler, which then calls _exit.
// Then removes (rmdir: only when empty) every folder listed below, so a signal leaves no folder
// a command created for its outputs either (e.g. `demo --out` after Ctrl-C).
void RemoveLiveTemporaryFiles() noexcept;

// A folder a command created for its outputs, listed for RemoveLiveTemporaryFiles. Returns a
// handle for UnlistCreatedFolder, or -1 (table full, path too long: then only the command's own
// cleanup removes it).
int ListCreatedFolder(const std::string& path);
// Removes a folder from the list (the command cleaned up or kept it).
void UnlistCreatedFolder(int handle);

}  // namespace gyrocomp
