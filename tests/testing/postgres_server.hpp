#pragma once

#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace fleetnav::testing {

/// A real PostgreSQL server for one test process: `initdb` into a temporary directory (as the
/// `postgres` user when the tests run as root, since PostgreSQL refuses root), started with
/// `pg_ctl` on a free loopback port with trust authentication, stopped (-m immediate) and
/// removed on destruction. The binaries come from the Debian packages the bootstrap installs
/// (postgresql-15). fsync is off: tests kill clients, never the machine.
class TemporaryPostgres {
 public:
  static absl::StatusOr<std::unique_ptr<TemporaryPostgres>> Start();
  ~TemporaryPostgres();
  TemporaryPostgres(const TemporaryPostgres&) = delete;
  TemporaryPostgres& operator=(const TemporaryPostgres&) = delete;

  /// Creates an empty database and returns its URI (postgresql://fleetnav@127.0.0.1:PORT/NAME).
  absl::StatusOr<std::string> CreateDatabase(const std::string& name);
  /// Stops the server at once, as a crash or a lost machine would (clients see it gone).
  absl::Status Kill();
  /// Starts it again on the same port and data.
  absl::Status Restart();
  int port() const { return port_; }

 private:
  TemporaryPostgres(std::string dir, int port) : dir_(std::move(dir)), port_(port) {}
  absl::Status PgCtl(const std::string& action);

  std::string dir_;
  int port_;
};

/// The process's server, started on first use and stopped at exit.
absl::StatusOr<TemporaryPostgres*> SharedPostgres();

/// A new empty database on the process's server, named `stem` with the process id and a
/// counter; returns its URI.
absl::StatusOr<std::string> NewSharedDatabase(const std::string& stem);

}  // namespace fleetnav::testing
