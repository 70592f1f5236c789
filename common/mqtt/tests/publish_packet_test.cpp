// Unit: QoS 0 PUBLISH packets byte by byte as MQTT 3.1.1 clauses 2.2 and 3.3 lay them out.
#include "common/mqtt/publish_packet.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace tb::mqtt {
namespace {

std::vector<unsigned> ubytes(const std::string& s) {
  std::vector<unsigned> v;
  for (const char c : s) {
    v.push_back(static_cast<unsigned char>(c));
  }
  return v;
}

TEST(Qos0Publish, SmallPacketLaidOutAsClause33) {
  std::string out;
  append_qos0_publish(out, "a/b", "hi", false);
  // Fixed header 0x30 (PUBLISH, DUP 0, QoS 0, RETAIN 0), Remaining Length 7 = 2 + 3 + 2, the
  // topic with its two-byte length, no packet identifier at QoS 0, the payload.
  EXPECT_EQ(ubytes(out), (std::vector<unsigned>{0x30, 7, 0, 3, 'a', '/', 'b', 'h', 'i'}));
}

TEST(Qos0Publish, RetainSetsBitZero) {
  std::string out;
  append_qos0_publish(out, "t", "", true);
  EXPECT_EQ(ubytes(out), (std::vector<unsigned>{0x31, 3, 0, 1, 't'}));
}

TEST(Qos0Publish, AppendsBehindWhatIsThere) {
  std::string out;
  append_qos0_publish(out, "x", "1", false);
  append_qos0_publish(out, "y", "2", false);
  EXPECT_EQ(ubytes(out), (std::vector<unsigned>{0x30, 4, 0, 1, 'x', '1', 0x30, 4, 0, 1, 'y', '2'}));
}

// Clause 2.2.3's table: the largest value of each length of the encoding and the next one.
struct LengthCase {
  std::size_t remaining;
  std::vector<unsigned> encoded;
};

TEST(Qos0Publish, RemainingLengthAtEachBoundary) {
  const std::vector<LengthCase> cases = {
      {127, {0x7f}},
      {128, {0x80, 0x01}},
      {16'383, {0xff, 0x7f}},
      {16'384, {0x80, 0x80, 0x01}},
      {2'097'151, {0xff, 0xff, 0x7f}},
      {2'097'152, {0x80, 0x80, 0x80, 0x01}},
  };
  for (const LengthCase& c : cases) {
    std::string out;
    const std::string payload(c.remaining - 2 - 1, 'p');  // topic "t": 2 + 1 bytes
    append_qos0_publish(out, "t", payload, false);
    ASSERT_EQ(out.size(), 1 + c.encoded.size() + c.remaining) << c.remaining;
    const std::vector<unsigned> head = ubytes(out.substr(1, c.encoded.size()));
    EXPECT_EQ(head, c.encoded) << "remaining length " << c.remaining;
    EXPECT_EQ(static_cast<unsigned char>(out[1 + c.encoded.size()]), 0u);
    EXPECT_EQ(out[1 + c.encoded.size() + 2], 't');
  }
}

TEST(Qos0Publish, TopicLengthUsesBothBytes) {
  const std::string topic(300, 'a');
  std::string out;
  append_qos0_publish(out, topic, "", false);
  // Remaining Length 302 = 0xae 0x02; topic length 300 = 0x01 0x2c, most significant first.
  EXPECT_EQ(ubytes(out.substr(0, 5)), (std::vector<unsigned>{0x30, 0xae, 0x02, 0x01, 0x2c}));
  EXPECT_EQ(out.size(), 3u + 302u);
}

TEST(Qos0Publish, RefusesWhatIsNotATopicNameAndLeavesTheBufferAlone) {
  const std::vector<std::string> bad = {
      "",                       // empty (clause 4.7.3)
      "its/+/cam",              // single-level wildcard
      "its/#",                  // multi-level wildcard
      std::string("a\0b", 3),   // NUL (clause 1.5.3)
      std::string("a\xff", 2),  // not UTF-8
      std::string(65536, 'a'),  // longer than a two-byte length
  };
  for (const std::string& t : bad) {
    std::string out = "kept";
    EXPECT_THROW(append_qos0_publish(out, t, "p", false), PacketError) << t.size();
    EXPECT_EQ(out, "kept");
  }
}

TEST(Qos0Publish, ErrorNamesTheTopic) {
  std::string out;
  try {
    append_qos0_publish(out, "its/1001/#", "p", false);
    FAIL() << "no error";
  } catch (const PacketError& e) {
    EXPECT_NE(std::string(e.what()).find("its/1001/#"), std::string::npos) << e.what();
  }
}

TEST(Qos0Publish, RefusesAPacketLargerThanTheEncodingHolds) {
  std::string out;
  const std::string payload(kMaxRemainingLength - 2 - 1 + 1, 'p');
  EXPECT_THROW(append_qos0_publish(out, "t", payload, false), PacketError);
  EXPECT_TRUE(out.empty());
}

}  // namespace
}  // namespace tb::mqtt
