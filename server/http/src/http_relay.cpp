#include "fleetnav/server/http/http_relay.hpp"

#include <httplib.h>
#include <openssl/ssl.h>
#include <openssl/x509_vfy.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "absl/strings/match.h"
#include "absl/strings/numbers.h"
#include "absl/strings/str_cat.h"
#include "absl/synchronization/mutex.h"
#include "absl/time/time.h"
#include "fleetnav/core/status_macros.hpp"
#include "http_listener.hpp"

namespace fleetnav::server::http {
namespace {

void SendError(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

/// Request headers passed on to the leader; the others belong to this hop.
constexpr const char* kPassedHeaders[] = {"Authorization", "Accept", "Content-Type",
                                          "Last-Event-ID"};

/// One request relayed: the leader's answer as it arrives, handed from the thread that reads it
/// to the server's worker that writes it to the caller.
struct Exchange {
  bool Answered() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex) { return answered || done; }
  bool Done() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex) { return done; }
  bool HasNews() const ABSL_EXCLUSIVE_LOCKS_REQUIRED(mutex) { return done || !pending.empty(); }
  /// Stops reading (at the leader's next message or timeout) and joins the reader.
  void Finish() {
    {
      absl::MutexLock lock(&mutex);
      abandoned = true;
    }
    if (reader.joinable()) reader.join();
  }

  absl::Mutex mutex;
  bool answered ABSL_GUARDED_BY(mutex) = false;  ///< status and types are known
  bool done ABSL_GUARDED_BY(mutex) = false;      ///< the reader has finished
  bool abandoned ABSL_GUARDED_BY(mutex) = false;
  int status ABSL_GUARDED_BY(mutex) = 0;
  std::string content_type ABSL_GUARDED_BY(mutex);
  std::string cache_control ABSL_GUARDED_BY(mutex);
  std::string pending ABSL_GUARDED_BY(mutex);  ///< body received, not passed on yet
  std::string error ABSL_GUARDED_BY(mutex);    ///< why the leader was not reached
  std::thread reader;
};

std::pair<time_t, time_t> SecondsAndMicros(double seconds) {
  const double whole = std::floor(seconds);
  return {static_cast<time_t>(whole), static_cast<time_t>((seconds - whole) * 1e6)};
}

}  // namespace

absl::Status HttpRelayParams::Validate() const {
  RETURN_IF_ERROR(ValidateHttpListen(listen_address, cert_path, key_path, threads));
  if (!(upstream_timeout_s > 0.0 && upstream_timeout_s <= 300.0)) {
    return absl::InvalidArgumentError(
        absl::StrCat("http upstream timeout: must be in (0, 300] s, got ", upstream_timeout_s));
  }
  return absl::OkStatus();
}

HttpRelay::HttpRelay(std::function<std::string()> leader, HttpRelayParams params)
    : leader_(std::move(leader)), params_(std::move(params)) {}

HttpRelay::~HttpRelay() { Stop(); }

absl::StatusOr<int> HttpRelay::Start() {
  if (absl::Status valid = params_.Validate(); !valid.ok()) return valid;
  ASSIGN_OR_RETURN(http_, MakeHttpServer(params_.cert_path, params_.key_path,
                                         params_.max_request_bytes, params_.threads));
  http_->Get("/healthz", [](const httplib::Request&, httplib::Response& res) {
    res.set_content("ok\n", "text/plain");
  });
  const auto relay = [this](const httplib::Request& req, httplib::Response& res) {
    Relay(req, res);
  };
  http_->Get(".*", relay);
  http_->Post(".*", relay);
  http_->set_error_handler([](const httplib::Request&, httplib::Response& res) {
    if (res.body.empty()) {
      res.set_content(
          nlohmann::json{{"error", res.status == 413 ? "request too large" : "bad request"}}.dump(),
          "application/json");
    }
  });
  ASSIGN_OR_RETURN(const int bound, BindHttpServer(http_.get(), params_.listen_address));
  listener_ = std::thread([this] { http_->listen_after_bind(); });
  return bound;
}

void HttpRelay::Stop() {
  if (http_ == nullptr || stopping_.exchange(true)) return;
  http_->stop();
  if (listener_.joinable()) listener_.join();
}

void HttpRelay::Relay(const httplib::Request& req, httplib::Response& res) {
  const std::string leader = leader_();
  if (leader.empty()) return SendError(res, 503, "no leader for this site yet; retry");
  const size_t colon = leader.rfind(':');
  int port = 0;
  if (colon == std::string::npos || !absl::SimpleAtoi(leader.substr(colon + 1), &port)) {
    return SendError(res, 502,
                     absl::StrCat("the leader's dashboard address '", leader, "' is bad"));
  }
  std::string host = leader.substr(0, colon);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    host = host.substr(1, host.size() - 2);
  }
  std::unique_ptr<httplib::ClientImpl> client;
  if (params_.upstream_ca_path.empty()) {
    client = std::make_unique<httplib::ClientImpl>(host, port);
  } else {
    auto https = std::make_unique<httplib::SSLClient>(host, port);
    https->set_ca_cert_path(params_.upstream_ca_path);
    https->enable_server_certificate_verification(true);
    // The pinned certificate is the whole chain of trust (it is no CA).
    if (SSL_CTX* context = https->ssl_context(); context != nullptr) {
      X509_STORE_set_flags(SSL_CTX_get_cert_store(context), X509_V_FLAG_PARTIAL_CHAIN);
      X509_VERIFY_PARAM_set_flags(SSL_CTX_get0_param(context), X509_V_FLAG_PARTIAL_CHAIN);
    }
    client = std::move(https);
  }
  const auto [seconds, micros] = SecondsAndMicros(params_.upstream_timeout_s);
  client->set_connection_timeout(seconds, micros);
  client->set_read_timeout(seconds, micros);
  client->set_write_timeout(seconds, micros);

  httplib::Request up;
  up.method = req.method;
  up.path = req.target.empty() ? req.path : req.target;
  for (const char* name : kPassedHeaders) {
    if (req.has_header(name)) up.headers.emplace(name, req.get_header_value(name));
  }
  // Uncompressed from the leader: the event stream must not wait in a compressor's buffer.
  up.headers.emplace("Accept-Encoding", "identity");
  up.body = req.body;
  auto exchange = std::make_shared<Exchange>();
  up.response_handler = [exchange](const httplib::Response& answer) {
    absl::MutexLock lock(&exchange->mutex);
    exchange->status = answer.status;
    exchange->content_type = answer.get_header_value("Content-Type");
    exchange->cache_control = answer.get_header_value("Cache-Control");
    exchange->answered = true;
    return !exchange->abandoned;
  };
  up.content_receiver = [exchange](const char* data, size_t length, uint64_t, uint64_t) {
    absl::MutexLock lock(&exchange->mutex);
    if (exchange->abandoned) return false;
    exchange->pending.append(data, length);
    return true;
  };
  exchange->reader = std::thread([exchange, client = std::move(client), up = std::move(up)] {
    const httplib::Result result = client->send(up);
    absl::MutexLock lock(&exchange->mutex);
    if (!result) exchange->error = httplib::to_string(result.error());
    exchange->done = true;
  });

  bool streaming = false;
  {
    absl::MutexLock lock(&exchange->mutex);
    exchange->mutex.Await(absl::Condition(exchange.get(), &Exchange::Answered));
    streaming = exchange->answered && exchange->status == 200 &&
                absl::StartsWith(exchange->content_type, "text/event-stream");
  }
  if (!streaming) {
    {
      absl::MutexLock lock(&exchange->mutex);
      exchange->mutex.Await(absl::Condition(exchange.get(), &Exchange::Done));
    }
    exchange->Finish();
    absl::MutexLock lock(&exchange->mutex);
    if (!exchange->answered) {
      return SendError(res, 502,
                       absl::StrCat("the site's leader did not answer at ", leader, " (",
                                    exchange->error, "); retry"));
    }
    res.status = exchange->status;
    if (!exchange->cache_control.empty()) res.set_header("Cache-Control", exchange->cache_control);
    res.set_content(exchange->pending,
                    exchange->content_type.empty() ? "text/plain" : exchange->content_type);
    return;
  }
  // An event stream: passed on as it comes until either side ends it.
  std::string content_type;
  {
    absl::MutexLock lock(&exchange->mutex);
    content_type = exchange->content_type;
  }
  res.set_header("Cache-Control", "no-store");
  res.set_chunked_content_provider(
      content_type,
      [this, exchange](size_t, httplib::DataSink& sink) {
        std::string chunk;
        bool done = false;
        {
          absl::MutexLock lock(&exchange->mutex);
          exchange->mutex.AwaitWithTimeout(absl::Condition(exchange.get(), &Exchange::HasNews),
                                           absl::Seconds(1));
          chunk.swap(exchange->pending);
          done = exchange->done;
        }
        if (stopping_.load()) return false;
        if (!chunk.empty() && !sink.write(chunk.data(), chunk.size())) return false;
        if (done) sink.done();
        return true;
      },
      [exchange](bool) { exchange->Finish(); });
}

}  // namespace fleetnav::server::http
