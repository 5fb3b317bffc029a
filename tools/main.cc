// gyrocomp: MEMS gyroscope denoising and temperature-drift compensation (Chang, Cao & Shen 2020).
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
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }
  try {
    for (const Command& c : commands) {
      if (c.app->parsed()) return c.run();
    }
  } catch (const std::exception& e) {
    std::cerr << "gyrocomp: internal error: " << e.what() << "\n";
    return kExitFailure;
  }
  return kExitBadInput;
}
