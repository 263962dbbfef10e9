#include "fleetnav/server/access/access_control.hpp"

namespace fleetnav::server {

absl::StatusOr<Caller> AccessControl::Authorize(absl::string_view method,
                                                const CallerCredentials& credentials) {
  absl::StatusOr<Caller> caller = policy()->Authorize(method, credentials);
  if (!caller.ok()) {
    Refused(caller.status());
  } else {
    admitted_.fetch_add(1, std::memory_order_relaxed);
  }
  return caller;
}

absl::StatusOr<Caller> AccessControl::AuthorizeHttp(bool action, absl::string_view authorization) {
  CallerCredentials credentials;
  credentials.authorization = std::string(authorization);
  return Authorize(action ? "/fleetnav.http/Act" : "/fleetnav.http/Read", credentials);
}

void AccessControl::Refused(const absl::Status& status) {
  if (absl::IsUnauthenticated(status)) {
    unauthenticated_.fetch_add(1, std::memory_order_relaxed);
  } else {
    denied_.fetch_add(1, std::memory_order_relaxed);
  }
  if (on_refusal_) on_refusal_(status.ToString());
}

void AccessControl::ReplacePolicy(std::shared_ptr<const AccessPolicy> policy) {
  absl::MutexLock lock(&policy_mutex_);
  policy_ = std::move(policy);
}

std::shared_ptr<const AccessPolicy> AccessControl::policy() const {
  absl::ReaderMutexLock lock(&policy_mutex_);
  return policy_;
}

AccessCounts AccessControl::counts() const {
  return {admitted_.load(std::memory_order_relaxed),
          unauthenticated_.load(std::memory_order_relaxed),
          denied_.load(std::memory_order_relaxed)};
}

}  // namespace fleetnav::server
