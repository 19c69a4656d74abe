// GetResult's messages built from serialized frames and probes: the same bytes as the
// message holding them parsed, and parsed back to the same frames and probes.
#include <gtest/gtest.h>

#include "server/service/encoded_result_chunk.h"

namespace mbstream {
namespace {

v1::Frame MakeFrame(int64_t seq) {
  v1::Frame frame;
  frame.set_seq(seq);
  frame.set_t_s(0.05 * static_cast<double>(seq));
  for (int j = 0; j < 6; ++j) {
    frame.add_q(0.1 * j + 1e-3 * static_cast<double>(seq));
    frame.add_qd(-0.2 * j);
    frame.add_tau(10.0 * j + 1.0);
  }
  frame.mutable_tcp_m()->set_x(0.5);
  frame.mutable_tcp_m()->set_z(1.25);
  frame.set_kinetic_j(0.0);  // a zero is not serialized
  frame.set_potential_j(-9.81);
  return frame;
}

TEST(EncodedResultChunkTest, SameBytesAsTheParsedMessage) {
  v1::ResultChunk parsed;
  EncodedResultChunk encoded;
  EXPECT_TRUE(encoded.empty());
  std::size_t bytes = 0;
  for (int64_t seq = 0; seq < 5; ++seq) {
    const v1::Frame frame = MakeFrame(seq);
    *parsed.add_frames() = frame;
    encoded.AddFrame(frame.SerializeAsString());
    bytes += frame.ByteSizeLong();
  }
  for (int64_t seq = 0; seq < 3; ++seq) {
    v1::ProbeReport& probe = *parsed.add_probes();
    probe.set_run_id("r-1");
    probe.set_seq(seq);
    probe.set_probe("tcp");
    probe.mutable_position_m()->set_y(0.25 * static_cast<double>(seq));
    encoded.AddProbe(probe);
    bytes += probe.ByteSizeLong();
  }
  EXPECT_FALSE(encoded.empty());
  EXPECT_EQ(encoded.bytes(), bytes);
  const std::string wire = encoded.message().SerializeAsString();
  EXPECT_EQ(wire, parsed.SerializeAsString());

  v1::ResultChunk received;
  ASSERT_TRUE(received.ParseFromString(wire));
  EXPECT_EQ(received.frames_size(), 5);
  EXPECT_EQ(received.probes_size(), 3);
  EXPECT_EQ(received.frames(4).SerializeAsString(), MakeFrame(4).SerializeAsString());
  EXPECT_EQ(received.probes(2).probe(), "tcp");

  // With the run's info: the parsed message's bytes still, the info first on the wire.
  encoded.mutable_info()->set_id("r-1");
  *parsed.mutable_info() = encoded.message().info();
  EXPECT_EQ(encoded.bytes(), bytes);
  const std::string with_info = encoded.message().SerializeAsString();
  ASSERT_TRUE(received.ParseFromString(with_info));
  EXPECT_EQ(received.info().id(), "r-1");
  EXPECT_EQ(received.frames_size(), 5);
  EXPECT_EQ(received.SerializeAsString(), parsed.SerializeAsString());
  EXPECT_EQ(with_info.substr(0, 1), std::string(1, '\x0a'));  // field 1, length-delimited

  encoded.Clear();
  EXPECT_TRUE(encoded.empty());
  EXPECT_EQ(encoded.bytes(), 0u);
  EXPECT_EQ(encoded.message().ByteSizeLong(), 0u);
  encoded.mutable_info()->set_id("r-2");
  EXPECT_FALSE(encoded.empty());  // an info alone is a message to send
}

}  // namespace
}  // namespace mbstream
