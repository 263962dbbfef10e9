#pragma once

#include <CLI/CLI.hpp>
#include <string>

namespace fleetnav::ctl {

/// A bash completion script for `app`, made from its own tree of subcommands and flags so that
/// it never falls behind the binary: `fleetnavctl completion bash > /etc/bash_completion.d/…`
/// or `source <(fleetnavctl completion bash)`. It completes subcommand names at each level and
/// the long flags of that level and the global ones; flag values are left to the shell.
std::string BashCompletionScript(const CLI::App& app, const std::string& program);

}  // namespace fleetnav::ctl
