// ROS bags (include/gyrocomp/io/bag.h): format detection, ROS 2 bag folders, rosbag2 per-file
// compression and the topic listing; the IMU / temperature collector is in bag_imu.cc.
#include "gyrocomp/io/bag.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "bag_bytes.h"

namespace gyrocomp {

namespace fs = std::filesystem;

namespace {

// MCAP spec "Magic"; sqlite3 fileformat2.html "1.3 The Database Header" (offset 0, 16 bytes);
// ROS wiki Bags/Format/2.0 "Version".
constexpr std::uint8_t kMcapMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
constexpr char kSqliteMagic[16] = "SQLite format 3";  // with its NUL: 16 bytes
constexpr char kRos1Magic[] = "#ROSBAG V2.0\n";

BagFormat DetectHead(const std::uint8_t* head, std::size_t n) {
  if (n >= 8 && std::memcmp(head, kMcapMagic, 8) == 0) return BagFormat::kMcap;
  if (n >= 16 && std::memcmp(head, kSqliteMagic, 16) == 0) return BagFormat::kRos2Sqlite;
  if (n >= 13 && std::memcmp(head, kRos1Magic, 13) == 0) return BagFormat::kRos1;
  return BagFormat::kNone;
}

// By the first 16 bytes; a Zstandard file (rosbag2 per-file compression) by the first 16 bytes
// it decompresses to.
BagFormat DetectFile(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return BagFormat::kNone;
  std::ifstream in(path, std::ios::binary);
  std::uint8_t head[16] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  const auto n = static_cast<std::size_t>(in.gcount());
  if (!bag_internal::HasZstdMagic(head, n)) return DetectHead(head, n);
  in.clear();
  in.seekg(0);
  std::ostringstream inner;
  if (!bag_internal::DecompressZstdFile(in, inner, sizeof head, true).empty()) return BagFormat::kNone;
  const std::string h = inner.str();
  return DetectHead(reinterpret_cast<const std::uint8_t*>(h.data()), h.size());
}

bool IsZstdFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::uint8_t head[4] = {};
  in.read(reinterpret_cast<char*>(head), sizeof head);
  return bag_internal::HasZstdMagic(head, static_cast<std::size_t>(in.gcount()));
}

// The storage files of a ROS 2 bag folder: metadata.yaml's rosbag2_bagfile_information.
// relative_file_paths list (rosbag2_storage/src/rosbag2_storage/metadata_io.cpp writes it as a
// YAML block sequence), else the folder's *.mcap / *.db3 in name order.
std::vector<std::string> FolderFiles(const std::string& dir) {
  std::vector<std::string> files;
  std::ifstream meta(dir + "/metadata.yaml");
  std::string line;
  bool in_list = false;
  while (std::getline(meta, line)) {
    const std::size_t b = line.find_first_not_of(" \t");
    if (b == std::string::npos) continue;
    const std::string t = line.substr(b);
    if (t.rfind("relative_file_paths:", 0) == 0) {
      in_list = true;
      continue;
    }
    if (!in_list) continue;
    if (t.rfind("- ", 0) != 0) break;
    std::string name = t.substr(2);
    while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
    if (name.size() >= 2 && (name.front() == '"' || name.front() == '\'')) name = name.substr(1, name.size() - 2);
    files.push_back(dir + "/" + name);
  }
  if (!files.empty()) return files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string ext = e.path().extension().string();
    const std::string stem_ext = e.path().stem().extension().string();
    if (ext == ".mcap" || ext == ".db3" || (ext == ".zstd" && (stem_ext == ".mcap" || stem_ext == ".db3"))) {
      files.push_back(e.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// metadata.yaml's rosbag2_bagfile_information.compression_mode ("", FILE or MESSAGE;
// rosbag2_storage metadata_io.cpp), unquoted.
std::string CompressionMode(const std::string& dir) {
  std::ifstream meta(dir + "/metadata.yaml");
  std::string line;
  while (std::getline(meta, line)) {
    const std::size_t at = line.find("compression_mode:");
    if (at == std::string::npos) continue;
    std::string v = line.substr(at + 17);
    v.erase(std::remove_if(v.begin(), v.end(), [](char c) { return c == ' ' || c == '"' || c == '\'' || c == '\r'; }), v.end());
    return v;
  }
  return "";
}

bool IsFolderBag(const std::string& path) {
  std::error_code ec;
  return fs::is_directory(path, ec) && fs::is_regular_file(path + "/metadata.yaml", ec);
}

// Channel ids of the k-th file of a folder are moved to (k << 32) + id, so files with their own
// numbering do not collide.
class OffsetVisitor : public BagVisitor {
 public:
  OffsetVisitor(BagVisitor* inner, std::uint64_t offset) : inner_(inner), offset_(offset) {}
  std::optional<Error> OnChannel(const BagChannel& c) override {
    BagChannel moved = c;
    moved.id += offset_;
    return inner_->OnChannel(moved);
  }
  bool Wants(std::uint64_t ch) const override { return inner_->Wants(ch + offset_); }
  std::optional<Error> OnMessage(const BagMessage& m) override {
    BagMessage moved = m;
    moved.channel += offset_;
    return inner_->OnMessage(moved);
  }
  void Count(std::uint64_t ch, std::uint64_t t) override { inner_->Count(ch + offset_, t); }
  void OnDamage(const LogDamage& d) override { inner_->OnDamage(d); }

 private:
  BagVisitor* inner_;
  std::uint64_t offset_;
};

std::optional<Error> StreamFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor);

// A temporary file removed (with sqlite3's side files) when it goes out of scope.
class TempFile {
 public:
  TempFile() {
    std::error_code ec;
    std::string pattern = (fs::temp_directory_path(ec) / "gyrocomp_bag_XXXXXX").string();
    const int fd = ::mkstemp(pattern.data());
    if (fd >= 0) {
      ::close(fd);
      path_ = pattern;
    }
  }
  ~TempFile() {
    if (path_.empty()) return;
    for (const char* side : {"", "-journal", "-wal", "-shm"}) std::remove((path_ + side).c_str());
  }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// rosbag2 per-file compression (rosbag2_compression, compression_mode FILE, format zstd): the
// storage file is Zstandard-compressed whole. sqlite3 needs a file and the MCAP reader seeks, so
// the file is stream-decompressed (bounded buffers) into a temporary file ($TMPDIR), read there
// and removed; errors name the compressed file.
std::optional<Error> StreamZstdFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  TempFile temp;
  if (temp.path().empty()) return IoError(path + ": cannot create a temporary file to decompress into");
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) return IoError(path + ": cannot open");
    std::ofstream out(temp.path(), std::ios::binary | std::ios::trunc);
    // Never more than the free space of the temporary folder (less 64 MiB for everyone else).
    std::error_code ec;
    const fs::space_info space = fs::space(fs::path(temp.path()).parent_path(), ec);
    const std::uint64_t margin = std::uint64_t{64} << 20;
    const std::uint64_t free_bytes = ec ? UINT64_MAX : (space.available > margin ? space.available - margin : 0);
    const std::uint64_t limit = std::min(options.max_decompressed_file_bytes, free_bytes);
    std::string why = bag_internal::DecompressZstdFile(in, out, limit);
    if (!why.empty() && limit < options.max_decompressed_file_bytes && why.find("compression bomb") != std::string::npos) {
      why = "decompresses to more than the " + std::to_string(limit) + " bytes free in " +
            fs::path(temp.path()).parent_path().string() + " (set TMPDIR to a folder with room)";
    }
    if (!why.empty()) return InvalidInput(path + ": " + why);
    out.close();
    if (!out) return IoError(path + ": cannot write the decompressed file " + temp.path() + " (disk full?)");
  }
  if (DetectFile(temp.path()) == BagFormat::kNone || IsZstdFile(temp.path())) {
    return InvalidInput(path + ": decompressed byte 0: not an MCAP, ROS 2 sqlite3 or ROS 1 v2.0 bag (by its first bytes)");
  }
  std::optional<Error> e = StreamFile(temp.path(), options, visitor);
  if (e) {
    // The reader named the temporary file: name the bag instead.
    const std::string decompressed = path + " (decompressed)";
    for (std::size_t at = e->message.find(temp.path()); at != std::string::npos;
         at = e->message.find(temp.path(), at + decompressed.size())) {
      e->message.replace(at, temp.path().size(), decompressed);
    }
  }
  return e;
}

std::optional<Error> StreamFile(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  if (IsZstdFile(path)) return StreamZstdFile(path, options, visitor);
  const BagFormat format = DetectFile(path);
  if (format == BagFormat::kRos2Sqlite) return StreamRos2Sqlite(path, options, visitor);
  if (format == BagFormat::kNone) {
    return InvalidInput(path + ": byte 0: not an MCAP, ROS 2 sqlite3 or ROS 1 v2.0 bag (by its first bytes)");
  }
  if (format == BagFormat::kRos1) return StreamRos1BagFile(path, options, visitor);
  std::ifstream in(path, std::ios::binary);
  if (!in) return IoError(path + ": cannot open");
  return StreamMcap(in, path, options, visitor);
}

// Counts every message per channel, decodes none.
class Lister : public BagVisitor {
 public:
  std::optional<Error> OnChannel(const BagChannel& c) override {
    auto [it, added] = index_.emplace(c.topic, topics_.size());
    if (added) topics_.push_back(BagTopicInfo{c.topic, c.type, c.encoding});
    channel_topic_[c.id] = it->second;
    return std::nullopt;
  }
  bool Wants(std::uint64_t) const override { return false; }
  std::optional<Error> OnMessage(const BagMessage&) override { return std::nullopt; }
  void Count(std::uint64_t ch, std::uint64_t t) override {
    const auto it = channel_topic_.find(ch);
    if (it == channel_topic_.end()) return;
    BagTopicInfo& info = topics_[it->second];
    if (info.messages == 0 || t < info.first_receive_ns) info.first_receive_ns = t;
    if (info.messages == 0 || t > info.last_receive_ns) info.last_receive_ns = t;
    ++info.messages;
  }
  void OnDamage(const LogDamage& d) override { damage_.push_back(d); }
  std::vector<BagTopicInfo> topics_;
  std::vector<LogDamage> damage_;

 private:
  std::map<std::string, std::size_t> index_;
  std::map<std::uint64_t, std::size_t> channel_topic_;
};

}  // namespace

std::string BagPosition::ToString() const {
  if (message_id) return "message id " + std::to_string(*message_id);
  std::string s = "byte " + std::to_string(offset);
  if (chunk_byte) s += ": chunk byte " + std::to_string(*chunk_byte);
  return s;
}

std::string_view BagFormatName(BagFormat format) {
  switch (format) {
    case BagFormat::kMcap: return "mcap";
    case BagFormat::kRos2Sqlite: return "ros2-sqlite3";
    case BagFormat::kRos1: return "rosbag1";
    default: return "none";
  }
}

BagFormat DetectBagFormat(const std::string& path) {
  if (path == "-") return BagFormat::kNone;
  if (IsFolderBag(path)) {
    const std::vector<std::string> files = FolderFiles(path);
    return files.empty() ? BagFormat::kNone : DetectFile(files.front());
  }
  return DetectFile(path);
}

bool BagReadOptions::IsValid(std::string* error) const {
  if (max_chunk_bytes == 0) {
    *error = "BagReadOptions::max_chunk_bytes = 0: must be > 0";
    return false;
  }
  if (max_decompressed_file_bytes == 0) {
    *error = "BagReadOptions::max_decompressed_file_bytes = 0: must be > 0";
    return false;
  }
  if (topic && topic->empty()) {
    *error = "BagReadOptions::topic is empty: name a topic or leave it unset";
    return false;
  }
  return true;
}

std::optional<double> BagTopicInfo::RateHz() const {
  if (messages < 2 || last_receive_ns <= first_receive_ns) return std::nullopt;
  return static_cast<double>(messages - 1) / (static_cast<double>(last_receive_ns - first_receive_ns) / 1e9);
}

std::optional<Error> StreamBag(const std::string& path, const BagReadOptions& options, BagVisitor* visitor) {
  std::string why;
  if (!options.IsValid(&why)) return InvalidArgument(why);
  if (!IsFolderBag(path)) return StreamFile(path, options, visitor);
  const std::vector<std::string> files = FolderFiles(path);
  if (files.empty()) return InvalidInput(path + ": a ROS 2 bag folder without .mcap or .db3 files");
  if (CompressionMode(path) == "MESSAGE") {
    return Unsupported(path + "/metadata.yaml: compression_mode MESSAGE (every message compressed on its own) is not "
                              "read; record with compression_mode FILE (read directly) or none");
  }
  for (std::size_t k = 0; k < files.size(); ++k) {
    OffsetVisitor moved(visitor, static_cast<std::uint64_t>(k) << 32);
    if (auto e = StreamFile(files[k], options, &moved)) return e;
  }
  return std::nullopt;
}

Result<BagListing> ListBag(const std::string& path, const BagReadOptions& options) {
  Lister lister;
  if (auto e = StreamBag(path, options, &lister)) return *e;
  BagListing out;
  out.source = path;
  out.format = DetectBagFormat(path);
  out.topics = std::move(lister.topics_);
  if (!lister.damage_.empty()) out.warnings.push_back(DamageWarning(path, lister.damage_));
  out.damage = std::move(lister.damage_);
  return out;
}

}  // namespace gyrocomp
