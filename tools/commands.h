// Registration of the gyrocomp subcommands. Each subcommand lives in its own file in tools/ and
// registers itself with a static CommandRegistrar, so adding one touches no other file:
//
//     namespace { Command Make(CLI::App& app) { ... }
//                 const CommandRegistrar kReg("allan", 30, &Make); }
//
// `order` sets the position in --help (pipeline order). Only subcommands that work register.
#pragma once

#include <vector>

#include "cli_common.h"

namespace gyrocomp::cli {

using CommandFactory = Command (*)(CLI::App& app);

struct CommandRegistrar {
  CommandRegistrar(const char* name, int order, CommandFactory factory);
};

// All registered factories, sorted by order.
std::vector<CommandFactory> RegisteredCommands();

}  // namespace gyrocomp::cli
