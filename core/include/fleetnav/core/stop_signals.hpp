#pragma once

#include <csignal>

namespace fleetnav {

/// Blocks SIGINT and SIGTERM in the calling thread, and so in every thread it starts after,
/// and returns the set: a daemon's main() calls it first and then waits for them with
/// sigwait() or sigtimedwait(), so that a stop request is taken at one known place.
sigset_t BlockStopSignals();

}  // namespace fleetnav
