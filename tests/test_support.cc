#include "test_support.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <random>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <gtest/gtest.h>

namespace gyrocomp::testing {

std::string GoldenPath(const std::string& relative) {
  return std::string(GYROCOMP_GOLDEN_DIR) + "/" + relative;
}

std::string RealdataPath(const std::string& relative) {
  const std::string p = std::string(GYROCOMP_REALDATA_DIR) + "/" + relative;
  return std::filesystem::exists(p) ? p : std::string();
}

std::string CliPath() { return GYROCOMP_CLI_PATH; }

nlohmann::json ReadJsonFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    ADD_FAILURE() << "cannot open " << path;
    return {};
  }
  return nlohmann::json::parse(in);
}

std::map<std::string, std::vector<double>> ReadGoldenCsv(const std::string& path) {
  std::map<std::string, std::vector<double>> out;
  std::ifstream in(path);
  if (!in) {
    ADD_FAILURE() << "cannot open " << path;
    return out;
  }
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::stringstream ss(line);
    std::string name;
    while (std::getline(ss, name, ',')) names.push_back(name);
  }
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::stringstream ss(line);
    std::string cell;
    std::size_t j = 0;
    while (std::getline(ss, cell, ',') && j < names.size()) {
      out[names[j++]].push_back(std::strtod(cell.c_str(), nullptr));
    }
  }
  return out;
}

namespace {

// Every directory MakeTempDir made in this process, removed at exit.
class TempDirRegistry {
 public:
  static TempDirRegistry& Get() {
    static TempDirRegistry registry;
    return registry;
  }
  void Add(const std::string& path) {
    std::lock_guard<std::mutex> lock(mutex_);
    paths_.push_back(path);
  }
  ~TempDirRegistry() {
    if (::getpid() != owner_) return;  // a forked child that called exit(): the parent's dirs
    for (const std::string& p : paths_) {
      std::error_code ec;
      std::filesystem::remove_all(p, ec);  // already gone (the test removed it): fine
    }
  }

 private:
  std::mutex mutex_;
  std::vector<std::string> paths_;
  pid_t owner_ = ::getpid();
};

}  // namespace

std::string MakeTempDir(const std::string& prefix) {
  std::random_device rd;
  const auto base = std::filesystem::temp_directory_path();
  TempDirRegistry& registry = TempDirRegistry::Get();  // constructed first, destroyed last
  for (int attempt = 0; attempt < 100; ++attempt) {
    auto p = base / (prefix + "_" + std::to_string(rd()));
    if (std::filesystem::create_directory(p)) {
      registry.Add(p.string());
      return p.string();
    }
  }
  ADD_FAILURE() << "cannot create a temp dir";
  return base.string();
}

TempDir::~TempDir() {
  std::error_code ec;
  std::filesystem::remove_all(path_, ec);
}

std::string WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
  EXPECT_TRUE(out.good()) << "cannot write " << path;
  return path;
}

std::string WriteGzFile(const std::string& path, const std::string& bytes) {
  gzFile gz = gzopen(path.c_str(), "wb");
  EXPECT_NE(gz, nullptr) << "cannot write " << path;
  if (gz == nullptr) return path;
  EXPECT_EQ(gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size())), static_cast<int>(bytes.size()));
  EXPECT_EQ(gzclose(gz), Z_OK);
  return path;
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

bool CancelledWhileRunning(CancellationToken& token, const std::function<void()>& call, const std::string& what) {
  std::chrono::steady_clock::time_point set_at;
  std::thread canceller([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    set_at = std::chrono::steady_clock::now();
    token.Cancel();
  });
  bool cancelled = false;
  try {
    call();
  } catch (const Cancelled&) {
    cancelled = true;
  } catch (...) {
    canceller.join();
    throw;
  }
  const auto end = std::chrono::steady_clock::now();
  canceller.join();
  std::printf("  %s: %s %.4f s after the token was set\n", what.c_str(), cancelled ? "cancelled" : "finished",
              std::chrono::duration<double>(end - set_at).count());
  return cancelled;
}

bool Sanitized() {
  const char* v = std::getenv("GYROCOMP_SANITIZED");
  return v != nullptr && std::string(v) == "1";
}

int RunCommand(const std::string& command, std::string* output) {
  std::string full = command + " 2>&1";
  FILE* pipe = popen(full.c_str(), "r");
  if (!pipe) return -1;
  char buf[4096];
  std::string text;
  while (std::size_t n = fread(buf, 1, sizeof buf, pipe)) text.append(buf, n);
  const int status = pclose(pipe);
  if (output) *output = text;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace gyrocomp::testing
