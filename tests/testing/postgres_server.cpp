#include "postgres_server.hpp"

#include <libpq-fe.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>

#include "absl/strings/str_cat.h"

namespace fleetnav::testing {
namespace {

/// A port the kernel just handed out on loopback (free now; the server binds it next).
int FreeLoopbackPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  socklen_t length = sizeof(address);
  int port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
    port = ntohs(address.sin_port);
  }
  ::close(fd);
  return port;
}

/// Runs `command` as the postgres user when this process is root.
absl::Status RunAsOwner(const std::string& command) {
  const std::string line =
      ::geteuid() == 0 ? absl::StrCat("runuser -u postgres -- ", command) : command;
  if (std::system(line.c_str()) != 0) {
    return absl::InternalError(absl::StrCat("test PostgreSQL: failed: ", line));
  }
  return absl::OkStatus();
}

}  // namespace

absl::StatusOr<std::unique_ptr<TemporaryPostgres>> TemporaryPostgres::Start() {
  static std::atomic<int> counter{0};
  const std::string dir = (std::filesystem::temp_directory_path() /
                           absl::StrCat("fleetnav-pg-", ::getpid(), "-", counter++))
                              .string();
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  if (::geteuid() == 0) {
    if (std::system(absl::StrCat("chown postgres ", dir).c_str()) != 0) {
      return absl::InternalError("test PostgreSQL: cannot hand " + dir + " to the postgres user");
    }
  }
  const int port = FreeLoopbackPort();
  std::unique_ptr<TemporaryPostgres> server(new TemporaryPostgres(dir, port));
  if (absl::Status made = RunAsOwner(absl::StrCat(
          FLEETNAV_PG_BINDIR, "/initdb -D ", dir, "/data -U fleetnav --auth=trust -E UTF8 ",
          "--no-sync --no-instructions >", dir, "/initdb.log 2>&1"));
      !made.ok()) {
    return made;
  }
  if (absl::Status started = server->PgCtl("start"); !started.ok()) return started;
  return server;
}

absl::Status TemporaryPostgres::PgCtl(const std::string& action) {
  if (action == "start") {
    return RunAsOwner(absl::StrCat(
        FLEETNAV_PG_BINDIR, "/pg_ctl -D ", dir_, "/data -l ", dir_, "/server.log -w -o '-p ", port_,
        " -k ", dir_, " -c listen_addresses=127.0.0.1 -c fsync=off' start >/dev/null"));
  }
  return RunAsOwner(
      absl::StrCat(FLEETNAV_PG_BINDIR, "/pg_ctl -D ", dir_, "/data -m immediate stop >/dev/null"));
}

TemporaryPostgres::~TemporaryPostgres() {
  (void)PgCtl("stop");
  std::error_code ignored;
  std::filesystem::remove_all(dir_, ignored);
}

absl::Status TemporaryPostgres::Kill() { return PgCtl("stop"); }

absl::Status TemporaryPostgres::Restart() { return PgCtl("start"); }

absl::StatusOr<std::string> TemporaryPostgres::CreateDatabase(const std::string& name) {
  const std::string admin = absl::StrCat("postgresql://fleetnav@127.0.0.1:", port_, "/postgres");
  PGconn* conn = PQconnectdb(admin.c_str());
  absl::Status status;
  if (PQstatus(conn) != CONNECTION_OK) {
    status = absl::UnavailableError(absl::StrCat("test PostgreSQL: ", PQerrorMessage(conn)));
  } else {
    PGresult* result = PQexec(conn, absl::StrCat("CREATE DATABASE \"", name, "\"").c_str());
    if (PQresultStatus(result) != PGRES_COMMAND_OK) {
      status = absl::InternalError(absl::StrCat("test PostgreSQL: ", PQerrorMessage(conn)));
    }
    PQclear(result);
  }
  PQfinish(conn);
  if (!status.ok()) return status;
  return absl::StrCat("postgresql://fleetnav@127.0.0.1:", port_, "/", name);
}

absl::StatusOr<TemporaryPostgres*> SharedPostgres() {
  static absl::StatusOr<std::unique_ptr<TemporaryPostgres>>* server =
      new absl::StatusOr<std::unique_ptr<TemporaryPostgres>>(TemporaryPostgres::Start());
  static const bool kStopAtExit = [] {
    std::atexit([] {
      if (server->ok()) server->value().reset();
    });
    return true;
  }();
  (void)kStopAtExit;
  if (!server->ok()) return server->status();
  return server->value().get();
}

absl::StatusOr<std::string> NewSharedDatabase(const std::string& stem) {
  absl::StatusOr<TemporaryPostgres*> server = SharedPostgres();
  if (!server.ok()) return server.status();
  static std::atomic<int> counter{0};
  return (*server)->CreateDatabase(absl::StrCat(stem, "_", ::getpid(), "_", counter++));
}

}  // namespace fleetnav::testing
