// gyrocomp: MEMS gyroscope denoising and temperature-drift compensation (Chang, Cao & Shen 2020).
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <exception>
#include <iostream>
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
  InstallSignalHandlers();
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
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
