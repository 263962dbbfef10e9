#include "fleetnav/server/rpc/replica_relay.hpp"

#include <openssl/crypto.h>
#include <openssl/evp.h>
#include <openssl/hmac.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <array>
#include <memory>

namespace fleetnav::server {
namespace {

using BioPtr = std::unique_ptr<BIO, decltype(&BIO_free)>;

BioPtr MemoryBio(const std::string& pem) {
  return BioPtr(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())), &BIO_free);
}

/// What the HMAC is taken over: names the purpose, so the key serves for nothing else.
constexpr absl::string_view kRelayLabel = "fleetnav replica relay v1";

}  // namespace

absl::StatusOr<std::string> ReplicaRelayKey(const std::string& private_key_pem) {
  BioPtr bio = MemoryBio(private_key_pem);
  std::unique_ptr<EVP_PKEY, decltype(&EVP_PKEY_free)> key(
      PEM_read_bio_PrivateKey(bio.get(), nullptr, nullptr, nullptr), &EVP_PKEY_free);
  if (key == nullptr) return absl::InvalidArgumentError("relay key: no PEM private key");
  unsigned char* der = nullptr;
  const int der_length = i2d_PrivateKey(key.get(), &der);
  if (der_length <= 0) return absl::InvalidArgumentError("relay key: cannot encode the key");
  std::array<unsigned char, EVP_MAX_MD_SIZE> mac{};
  unsigned int mac_length = 0;
  const unsigned char* made = HMAC(EVP_sha256(), der, der_length,
                                   reinterpret_cast<const unsigned char*>(kRelayLabel.data()),
                                   kRelayLabel.size(), mac.data(), &mac_length);
  OPENSSL_clear_free(der, static_cast<size_t>(der_length));
  if (made == nullptr) return absl::InternalError("relay key: HMAC failed");
  static constexpr char kHex[] = "0123456789abcdef";
  std::string hex;
  for (unsigned int i = 0; i < mac_length; ++i) {
    hex.push_back(kHex[mac[i] >> 4]);
    hex.push_back(kHex[mac[i] & 0xf]);
  }
  return hex;
}

bool IsReplicaRelayKey(absl::string_view presented, absl::string_view relay_key) {
  return !relay_key.empty() && presented.size() == relay_key.size() &&
         CRYPTO_memcmp(presented.data(), relay_key.data(), relay_key.size()) == 0;
}

absl::StatusOr<std::string> LeafCertificatePem(const std::string& chain_pem) {
  BioPtr in = MemoryBio(chain_pem);
  std::unique_ptr<X509, decltype(&X509_free)> leaf(
      PEM_read_bio_X509(in.get(), nullptr, nullptr, nullptr), &X509_free);
  if (leaf == nullptr) return absl::InvalidArgumentError("no PEM certificate in the chain");
  BioPtr out(BIO_new(BIO_s_mem()), &BIO_free);
  if (out == nullptr || PEM_write_bio_X509(out.get(), leaf.get()) != 1) {
    return absl::InternalError("cannot write the certificate as PEM");
  }
  char* data = nullptr;
  const long length = BIO_get_mem_data(out.get(), &data);
  return std::string(data, static_cast<size_t>(length));
}

}  // namespace fleetnav::server
