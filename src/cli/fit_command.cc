#include "cli/commands.h"
namespace hoof::cli {
void RegisterFit(CLI::App&, RunState&) {}
}  // namespace hoof::cli
