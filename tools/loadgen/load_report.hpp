#pragma once

#include <sys/types.h>

#include <vector>

namespace fleetnav::loadgen {

/// The p-th percentile (0-100) of samples (nearest rank); 0 for none.
double Percentile(std::vector<double> samples, double p);

/// CPU seconds (user + system) a process has used so far, from /proc; -1 if unknown.
double ProcessCpuSeconds(pid_t pid);
/// Resident set size of a process in MB, from /proc; -1 if unknown.
double ProcessRssMb(pid_t pid);
/// The process listening on TCP `port` on this machine, from /proc/net/tcp and the processes'
/// open sockets; -1 if none is found (or it belongs to another user).
pid_t ListeningPid(int port);

}  // namespace fleetnav::loadgen
