// gyrocomp: MEMS gyroscope denoising and temperature-drift compensation (Chang, Cao & Shen 2020).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <exception>
#include <iostream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "commands.h"

namespace gyrocomp::cli {
namespace {

struct Entry {
  const char* name;
  int order;
  CommandFactory factory;
};

std::vector<Entry>& Registry() {
  static std::vector<Entry> registry;
  return registry;
}

// SIGINT / SIGTERM / SIGHUP: remove the temporaries of the outputs being written, then exit with
// 128 + signal (the shell's convention). Async-signal-safe: RemoveLiveTemporaryFiles and _exit.
extern "C" void OnTerminatingSignal(int sig) {
  gyrocomp::RemoveLiveTemporaryFiles();
  _exit(128 + sig);
}

void InstallSignalHandlers() {
  struct sigaction action {};
  action.sa_handler = OnTerminatingSignal;
  sigemptyset(&action.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) sigaction(sig, &action, nullptr);
}

// Every seed option (--seed, --sim-seed, ...) takes a decimal integer in [0, 2^64 - 1]: CLI11
// would wrap "-1" and saturate "18446744073709551616" silently. Added here, once, for all
// subcommands, present and future.
void CheckSeedOptions(CLI::App& app) {
  const CLI::Validator seed_range(
      [](std::string& text) -> std::string {
        std::uint64_t value = 0;
        const auto r = std::from_chars(text.data(), text.data() + text.size(), value);
        if (text.empty() || r.ec != std::errc() || r.ptr != text.data() + text.size()) {
          return "seed '" + text + "': must be an integer in [0, 18446744073709551615]";
        }
        return "";
      },
      "UINT64");
  for (CLI::App* sub : app.get_subcommands({})) {
    for (CLI::Option* option : sub->get_options()) {
      const std::string name = option->get_name();
      if (name.size() >= 4 && name.compare(name.size() - 4, 4, "seed") == 0) option->check(seed_range);
    }
  }
}

// Numeric options: every FLOAT or INT option of every subcommand refuses, at parse time
// (before any work), NaN, infinities and magnitudes above kMaxOptionMagnitude; the options below
// are refused outside their valid range, which is the library's (the IsValid named beside each),
// with the range in the message. Other bounds are the library's IsValid, checked by each command
// before it reads its input.
constexpr double kMaxOptionMagnitude = 1e15;

struct OptionRange {
  const char* name;    // long option name, e.g. "--gamma"
  double lo, hi;
  bool lo_open, hi_open;
  const char* source;  // the IsValid that states the same range
};

constexpr OptionRange kOptionRanges[] = {
    {"--C", 0.0, 1e6, true, false, "SvrOptions"},
    {"--gamma", 0.0, 1e6, true, false, "SvrOptions"},
    {"--sigma", 1e-3, 1e3, false, false, "SvrOptions"},
    {"--epsilon", 0.0, 1e6, false, false, "SvrOptions"},
    {"--svr-tol", 0.0, 1.0, true, false, "SvrOptions::tolerance"},
    {"--C-min", 0.0, 1e6, true, false, "SvrSearchOptions"},
    {"--C-max", 0.0, 1e6, true, false, "SvrSearchOptions"},
    {"--sigma-min", 1e-3, 1e3, false, false, "SvrSearchOptions"},
    {"--sigma-max", 1e-3, 1e3, false, false, "SvrSearchOptions"},
    {"--tau", 0.0, 2.0, false, false, "VmdOptions::tau"},
    {"--alpha", 0.0, kMaxOptionMagnitude, true, false, "VmdOptions::alpha"},
    {"--tol", 0.0, kMaxOptionMagnitude, true, false, "VmdOptions::tol"},
    {"--modes", 1.0, 1000.0, false, false, "VmdOptions::num_modes"},
    {"--max-iter", 2.0, 1e9, false, false, "VmdOptions::max_iterations"},
    {"--m", 1.0, 10.0, false, false, "SampleEntropyOptions::m"},
    {"--r", 0.0, kMaxOptionMagnitude, true, false, "SampleEntropyOptions::r_factor"},
    {"--r-abs", 0.0, kMaxOptionMagnitude, true, false, "SampleEntropyOptions::r_absolute"},
    {"--flp-order", 1.0, 4096.0, false, false, "FlpOptions::order"},
    {"--flp-beta", 0.0, 2.0, true, true, "FlpOptions::beta"},
    {"--flp-alpha", 0.0, kMaxOptionMagnitude, true, false, "FlpOptions::alpha"},
    {"--flp-forgetting", 0.0, 1.0, false, true, "FlpOptions::power_forgetting"},
    {"--pa", 0.0, 1.0, false, false, "CuckooSearchOptions::discovery_probability"},
    {"--nests", 2.0, 1e6, false, false, "CuckooSearchOptions::num_nests"},
    {"--generations", 0.0, 1e6, false, false, "CuckooSearchOptions::max_generations"},
    {"--fs", 1e-6, 1e9, false, false, "LogSpec::fs_hz"},
    {"--resample", 1e-6, 1e9, false, false, "LogSpec::resample_hz"},
    {"--max-memory", 0.0, kMaxOptionMagnitude, true, false, "LogSpec::max_memory_bytes"},
};

std::string RangeText(double lo, double hi, bool lo_open, bool hi_open) {
  std::ostringstream os;
  os << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  return os.str();
}

void CheckNumericOptions(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands({})) {
    for (CLI::Option* option : sub->get_options()) {
      const std::string type = option->get_type_name();
      const bool is_float = type.rfind("FLOAT", 0) == 0;
      const bool is_int = type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0;
      const std::string name = option->get_name();
      const bool is_seed = name.size() >= 4 && name.compare(name.size() - 4, 4, "seed") == 0;  // CheckSeedOptions
      if ((!is_float && !is_int) || is_seed) continue;
      const OptionRange* range = nullptr;
      for (const OptionRange& r : kOptionRanges) {
        if (name == r.name) range = &r;
      }
      // CLI11's PositiveNumber / NonNegativeNumber print "not in range 0.000000 to 1797...": the
      // same rule with a readable range.
      static constexpr OptionRange kPositive{"", 0.0, kMaxOptionMagnitude, true, false, "> 0"};
      static constexpr OptionRange kNonNegative{"", 0.0, kMaxOptionMagnitude, false, false, ">= 0"};
      if (range == nullptr && type.find(":POSITIVE") != std::string::npos) range = &kPositive;
      if (range == nullptr && type.find(":NONNEGATIVE") != std::string::npos) range = &kNonNegative;
      if (range != nullptr) {
        // The range replaces CLI11's own checks (PositiveNumber: a two-line message with 1.8e308).
        try {
          for (int i = 0;; ++i) option->get_validator(i)->active(false);
        } catch (const CLI::OptionNotFound&) {  // past the last validator
        }
      }
      option->check(CLI::Validator(
          [range, unsigned_type = type.rfind("UINT", 0) == 0](std::string& text) -> std::string {
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            if (text.empty() || end != text.c_str() + text.size()) return "";  // CLI11 reports what is not a number
            if (range != nullptr) {
              const bool ok = (range->lo_open ? v > range->lo : v >= range->lo) &&
                              (range->hi_open ? v < range->hi : v <= range->hi);
              if (!ok) {
                return text + ": must be in " + RangeText(range->lo, range->hi, range->lo_open, range->hi_open) + " (" +
                       range->source + ")";
              }
            }
            if (!std::isfinite(v) || std::abs(v) > kMaxOptionMagnitude) {
              std::ostringstream os;
              os << text << ": must be a finite number of magnitude <= " << kMaxOptionMagnitude;
              return os.str();
            }
            if (unsigned_type && v < 0) return text + ": must be >= 0";
            return "";
          },
          range != nullptr ? RangeText(range->lo, range->hi, range->lo_open, range->hi_open) : std::string(),
          "gyrocomp-range"));
    }
  }
}

// The first argument that is not an option names the subcommand: an unknown one is refused here,
// before CLI11 sees it, because with --help CLI11 would print the top-level help and exit 0
// (so that scripts can tell whether a subcommand exists).
Status CheckSubcommandName(CLI::App& app, int argc, char** argv) {
  if (argc < 2) return Status::Ok();
  const std::string first = argv[1];
  if (first.empty() || first[0] == '-') return Status::Ok();
  for (const CLI::App* sub : app.get_subcommands({})) {
    if (sub->check_name(first)) return Status::Ok();
  }
  std::string names;
  for (const CLI::App* sub : app.get_subcommands({})) names += (names.empty() ? "" : ", ") + sub->get_name();
  return InvalidArgument("unknown subcommand '" + first + "' (subcommands: " + names + ")");
}

// Runs the parsed command inside the output transaction of cli_common.h.
int RunCommand(const Command& c) {
  const std::string name = c.app->get_name();
  if (Status s = PrepareFiles(c.app); !s) return ReportError(name, s.error());
  const int code = c.run();
  if (code != kExitOk) {
    Outputs().Discard();
    return code;
  }
  if (Status s = Outputs().Commit(); !s) {
    // Every destination was checked before the run: what fails now (ENOSPC, EIO) is not the
    // user's input.
    std::cerr << "gyrocomp " << name << ": error: " << s.error().message << "\n";
    return kExitFailure;
  }
  return kExitOk;
}

}  // namespace

CommandRegistrar::CommandRegistrar(const char* name, int order, CommandFactory factory) {
  Registry().push_back({name, order, factory});
}

std::vector<CommandFactory> RegisteredCommands() {
  std::vector<Entry> entries = Registry();
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.order < b.order; });
  std::vector<CommandFactory> out;
  for (const Entry& e : entries) out.push_back(e.factory);
  return out;
}

}  // namespace gyrocomp::cli

int main(int argc, char** argv) {
  using namespace gyrocomp::cli;
  CLI::App app{"gyrocomp: remove noise and temperature drift from MEMS gyroscope output "
               "(VMD-SE-WFLP-CS-SVR, Chang, Cao & Shen 2020)"};
  app.set_version_flag("--version", std::string("gyrocomp ") + GYROCOMP_VERSION);
  app.require_subcommand(1);
  std::vector<Command> commands;
  for (CommandFactory make : RegisteredCommands()) commands.push_back(make(app));
  CheckSeedOptions(app);
  CheckNumericOptions(app);
  InstallSignalHandlers();
  if (gyrocomp::Status s = CheckSubcommandName(app, argc, argv); !s) {
    std::cerr << "gyrocomp: error: " << s.error().message << "\n";
    return kExitBadInput;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    // One line (cli.md), prefixed with the subcommand when there is one; no "Run with --help".
    std::string where = "gyrocomp";
    for (const CLI::App* sub : app.get_subcommands({})) {
      if (argc > 1 && sub->check_name(argv[1])) where += " " + sub->get_name();
    }
    std::string what = e.what();
    std::replace(what.begin(), what.end(), '\n', ' ');
    std::cerr << where << ": error: " << what << "\n";
    return kExitBadInput;
  }
  try {
    for (const Command& c : commands) {
      if (c.app->parsed()) return RunCommand(c);
    }
  } catch (const std::exception& e) {
    Outputs().Discard();
    std::cerr << "gyrocomp: internal error: " << e.what() << "\n";
    return kExitFailure;
  }
  return kExitBadInput;
}
