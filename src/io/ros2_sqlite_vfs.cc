// The sqlite3 VFS the rosbag2 reader opens .db3 files with (ros2_sqlite_reader.h): the default
// VFS, except that a read past the end of the file is an error SQLite reports as damage. SQLite
// itself fills the missing bytes of a short read with zeros and goes on (sqlite3 c3ref/io_methods:
// "If xRead() returns SQLITE_IOERR_SHORT_READ it must also fill in the unread portions of the
// buffer with zeros"), so the last page of a file cut inside it would be read as rows whose data
// end in zeros: rows the bag never held, which may still decode. As SQLITE_CORRUPT that page is
// skipped like any damaged page (ros2_sqlite_recovery.cc).
#include <cstring>
#include <mutex>

#include "ros2_sqlite_reader.h"

namespace gyrocomp::ros2_sqlite_internal {

namespace {

// An open file: the default VFS's file object follows this header in the same allocation.
struct File {
  sqlite3_file base;
  sqlite3_file* real;
};
sqlite3_file* Real(sqlite3_file* f) { return reinterpret_cast<File*>(f)->real; }

int Read(sqlite3_file* f, void* buf, int n, sqlite3_int64 at) {
  const int rc = Real(f)->pMethods->xRead(Real(f), buf, n, at);
  return rc == SQLITE_IOERR_SHORT_READ ? SQLITE_CORRUPT : rc;
}

// Everything else goes to the default VFS's file unchanged.
int Close(sqlite3_file* f) { return Real(f)->pMethods->xClose(Real(f)); }
int Write(sqlite3_file* f, const void* b, int n, sqlite3_int64 at) { return Real(f)->pMethods->xWrite(Real(f), b, n, at); }
int Truncate(sqlite3_file* f, sqlite3_int64 size) { return Real(f)->pMethods->xTruncate(Real(f), size); }
int Sync(sqlite3_file* f, int flags) { return Real(f)->pMethods->xSync(Real(f), flags); }
int FileSize(sqlite3_file* f, sqlite3_int64* size) { return Real(f)->pMethods->xFileSize(Real(f), size); }
int Lock(sqlite3_file* f, int level) { return Real(f)->pMethods->xLock(Real(f), level); }
int Unlock(sqlite3_file* f, int level) { return Real(f)->pMethods->xUnlock(Real(f), level); }
int CheckReservedLock(sqlite3_file* f, int* out) { return Real(f)->pMethods->xCheckReservedLock(Real(f), out); }
int FileControl(sqlite3_file* f, int op, void* arg) { return Real(f)->pMethods->xFileControl(Real(f), op, arg); }
int SectorSize(sqlite3_file* f) { return Real(f)->pMethods->xSectorSize(Real(f)); }
int DeviceCharacteristics(sqlite3_file* f) { return Real(f)->pMethods->xDeviceCharacteristics(Real(f)); }
int ShmMap(sqlite3_file* f, int region, int size, int extend, void volatile** p) {
  return Real(f)->pMethods->xShmMap(Real(f), region, size, extend, p);
}
int ShmLock(sqlite3_file* f, int offset, int n, int flags) { return Real(f)->pMethods->xShmLock(Real(f), offset, n, flags); }
void ShmBarrier(sqlite3_file* f) { Real(f)->pMethods->xShmBarrier(Real(f)); }
int ShmUnmap(sqlite3_file* f, int remove) { return Real(f)->pMethods->xShmUnmap(Real(f), remove); }
// No memory-mapped reads: every page comes through Read.
int Fetch(sqlite3_file*, sqlite3_int64, int, void** p) {
  *p = nullptr;
  return SQLITE_OK;
}
int Unfetch(sqlite3_file*, sqlite3_int64, void*) { return SQLITE_OK; }

const sqlite3_io_methods kMethods = {3,        Close,       Read,     Write,   Truncate,   Sync,       FileSize,
                                     Lock,     Unlock,      CheckReservedLock, FileControl, SectorSize,
                                     DeviceCharacteristics, ShmMap,   ShmLock, ShmBarrier, ShmUnmap,   Fetch,
                                     Unfetch};

sqlite3_vfs g_vfs;

int Open(sqlite3_vfs* vfs, const char* name, sqlite3_file* f, int flags, int* out_flags) {
  auto* real_vfs = static_cast<sqlite3_vfs*>(vfs->pAppData);
  auto* file = reinterpret_cast<File*>(f);
  file->real = reinterpret_cast<sqlite3_file*>(file + 1);
  file->base.pMethods = nullptr;  // SQLite then does not call Close when the open fails
  const int rc = real_vfs->xOpen(real_vfs, name, file->real, flags, out_flags);
  if (rc == SQLITE_OK && file->real->pMethods != nullptr) file->base.pMethods = &kMethods;
  return rc;
}

}  // namespace

const char* ShortReadIsDamageVfs() {
  static std::once_flag once;
  std::call_once(once, [] {
    sqlite3_vfs* real = sqlite3_vfs_find(nullptr);
    std::memcpy(&g_vfs, real, sizeof g_vfs);
    g_vfs.iVersion = real->iVersion;
    g_vfs.szOsFile = static_cast<int>(sizeof(File)) + real->szOsFile;
    g_vfs.pNext = nullptr;
    g_vfs.zName = "gyrocomp-short-read-is-damage";
    g_vfs.pAppData = real;
    g_vfs.xOpen = Open;
    sqlite3_vfs_register(&g_vfs, 0);
  });
  return g_vfs.zName;
}

}  // namespace gyrocomp::ros2_sqlite_internal
