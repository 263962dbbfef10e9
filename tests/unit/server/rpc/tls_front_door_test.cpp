// What fleetnavd makes of gRPC's log line for a failed TLS handshake, without a network.
#include "fleetnav/server/rpc/tls_front_door.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace fleetnav::server {
namespace {

using ::testing::HasSubstr;

TEST(HandshakeRefusalReasonTest, NamesTheReasonsOperatorsMeet) {
  // The lines gRPC 1.51 logs (ssl_transport_security.cc) for a server-side handshake.
  EXPECT_THAT(HandshakeRefusalReason("Handshake failed with fatal error SSL_ERROR_SSL: "
                                     "error:0A000086:SSL routines::certificate verify failed.")
                  .value_or(""),
              HasSubstr("did not verify against the robot CA"));
  EXPECT_EQ(HandshakeRefusalReason("Handshake failed with fatal error SSL_ERROR_SSL: "
                                   "error:0A00010B:SSL routines::wrong version number.")
                .value_or(""),
            "not TLS (a plaintext client?)");
  EXPECT_EQ(HandshakeRefusalReason("Handshake failed with fatal error SSL_ERROR_SSL: "
                                   "error:0A000412:SSL routines::sslv3 alert bad certificate.")
                .value_or(""),
            "sslv3 alert bad certificate");
}

TEST(HandshakeRefusalReasonTest, OtherLinesAreNoRefusal) {
  EXPECT_FALSE(HandshakeRefusalReason("No match found for server name: elsewhere.").has_value());
  EXPECT_FALSE(HandshakeRefusalReason("").has_value());
}

}  // namespace
}  // namespace fleetnav::server
