#include "fleetnav/server/rpc/grpc_log_tap.hpp"

#include <grpc/support/log.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <map>
#include <mutex>
#include <string_view>

#include "absl/strings/ascii.h"
#include "absl/synchronization/mutex.h"

namespace fleetnav::server {
namespace {

/// The process's subscribers. Never destroyed: gRPC's threads may log while the process ends.
struct Subscribers {
  absl::Mutex mutex;
  std::map<uint64_t, GrpcLogTap::Listener> listeners ABSL_GUARDED_BY(mutex);
  uint64_t next_id ABSL_GUARDED_BY(mutex) = 1;
};

Subscribers& TheSubscribers() {
  static auto* subscribers = new Subscribers();
  return *subscribers;
}

/// The least severity the operator asked gRPC to print (GRPC_VERBOSITY; gRPC's default ERROR).
/// NONE prints nothing: one above ERROR.
int OperatorVerbosity() {
  const char* text = std::getenv("GRPC_VERBOSITY");
  const std::string verbosity = absl::AsciiStrToUpper(text != nullptr ? text : "ERROR");
  if (verbosity == "DEBUG") return GPR_LOG_SEVERITY_DEBUG;
  if (verbosity == "INFO") return GPR_LOG_SEVERITY_INFO;
  if (verbosity == "NONE") return GPR_LOG_SEVERITY_ERROR + 1;
  return GPR_LOG_SEVERITY_ERROR;
}

/// gRPC's own line ("E1127 07:35:46.763922705   20069 file.cc:1501] message"): its default log
/// function is not part of its public API, so the tap writes the same line itself.
void PrintLikeGrpc(const gpr_log_func_args& args) {
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  tm utc{};
  gmtime_r(&now.tv_sec, &utc);
  const std::string_view path = args.file != nullptr ? args.file : "";
  const std::string_view file = path.substr(path.rfind('/') + 1);
  const char letter = args.severity == GPR_LOG_SEVERITY_DEBUG  ? 'D'
                      : args.severity == GPR_LOG_SEVERITY_INFO ? 'I'
                                                               : 'E';
  std::fprintf(stderr, "%c%02d%02d %02d:%02d:%02d.%09ld %7ld %.*s:%d] %s\n", letter, utc.tm_mon + 1,
               utc.tm_mday, utc.tm_hour, utc.tm_min, utc.tm_sec, now.tv_nsec,
               static_cast<long>(syscall(SYS_gettid)), static_cast<int>(file.size()), file.data(),
               args.line, args.message != nullptr ? args.message : "");
}

void Tap(gpr_log_func_args* args) {
  static const int kOperatorVerbosity = OperatorVerbosity();
  if (static_cast<int>(args->severity) >= kOperatorVerbosity) PrintLikeGrpc(*args);
  if (args->severity != GPR_LOG_SEVERITY_ERROR || args->message == nullptr) return;
  Subscribers& subscribers = TheSubscribers();
  absl::MutexLock lock(&subscribers.mutex);
  for (const auto& [id, listener] : subscribers.listeners) listener(args->message);
}

}  // namespace

uint64_t GrpcLogTap::Subscribe(Listener listener) {
  static std::once_flag installed;
  std::call_once(installed, [] {
    // ERROR messages must reach the tap even when the operator silenced them (NONE); the tap
    // passes on only what GRPC_VERBOSITY asks for.
    if (OperatorVerbosity() > GPR_LOG_SEVERITY_ERROR) gpr_set_log_verbosity(GPR_LOG_SEVERITY_ERROR);
    gpr_set_log_function(&Tap);
  });
  Subscribers& subscribers = TheSubscribers();
  absl::MutexLock lock(&subscribers.mutex);
  const uint64_t id = subscribers.next_id++;
  subscribers.listeners.emplace(id, std::move(listener));
  return id;
}

void GrpcLogTap::Unsubscribe(uint64_t id) {
  Subscribers& subscribers = TheSubscribers();
  absl::MutexLock lock(&subscribers.mutex);
  subscribers.listeners.erase(id);
}

}  // namespace fleetnav::server
