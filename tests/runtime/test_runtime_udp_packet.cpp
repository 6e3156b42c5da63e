// SPDX-License-Identifier: Apache-2.0
// The network bridge's packets: the documented little-endian byte layout, round trips, and
// every kind of malformed datagram rejected with its reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include <smoothforce/runtime/servo_step.h>
#include <smoothforce/runtime/udp_packet.h>

namespace {

using namespace sf::rt;

/// The documented layout written independently of the codec: memcpy of the native value,
/// bytes reversed on a big-endian host.
template <class T>
void put(std::vector<uint8_t>& b, size_t at, T v) {
  uint8_t raw[sizeof(T)];
  std::memcpy(raw, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(raw, raw + sizeof(T));
  std::memcpy(b.data() + at, raw, sizeof(T));
}

std::vector<uint8_t> expectedHip(const HipPacket& p) {
  std::vector<uint8_t> b(56, 0);
  std::memcpy(b.data(), "SFHD", 4);
  put<uint16_t>(b, 4, 1);
  b[6] = 1;
  put<uint64_t>(b, 8, p.seq);
  put<double>(b, 16, p.senderTime);
  for (int i = 0; i < 3; ++i) put<double>(b, 24 + 8 * size_t(i), p.position[i]);
  put<uint32_t>(b, 48, p.buttons);
  return b;
}

std::vector<uint8_t> expectedForce(const ForcePacket& p) {
  std::vector<uint8_t> b(64, 0);
  std::memcpy(b.data(), "SFHD", 4);
  put<uint16_t>(b, 4, 1);
  b[6] = 2;
  put<uint64_t>(b, 8, p.seq);
  put<double>(b, 16, p.senderTime);
  put<double>(b, 24, p.loopTime);
  for (int i = 0; i < 3; ++i) put<double>(b, 32 + 8 * size_t(i), p.force[i]);
  put<uint32_t>(b, 56, p.status);
  put<uint32_t>(b, 60, p.fault);
  return b;
}

class RuntimeUdpPacket : public ::testing::Test {
 protected:
  std::mt19937_64 rng{42};
  double real() {  // finite doubles of every magnitude and sign, zeros and subnormals included
    switch (rng() % 6) {
      case 0:
        return 0.0;
      case 1:
        return -0.0;
      case 2:
        return std::numeric_limits<double>::denorm_min() * double(rng() % 1000);
      default: {
        double v;
        do v = std::bit_cast<double>(rng());
        while (!std::isfinite(v));
        return v;
      }
    }
  }
  HipPacket randomHip() {
    HipPacket p;
    p.seq = rng();
    p.senderTime = real();
    for (double& x : p.position) x = real();
    p.buttons = uint32_t(rng());
    return p;
  }
  ForcePacket randomForce() {
    ForcePacket p;
    p.seq = rng();
    p.senderTime = real();
    p.loopTime = real();
    for (double& x : p.force) x = real();
    p.status = uint32_t(rng());
    p.fault = uint32_t(rng());
    return p;
  }
};

TEST_F(RuntimeUdpPacket, LayoutIsTheDocumentedLittleEndianOne) {
  for (int i = 0; i < 2000; ++i) {
    const HipPacket h = randomHip();
    uint8_t hb[kHipPacketSize];
    encodeHip(h, hb);
    ASSERT_EQ(std::vector<uint8_t>(hb, hb + sizeof hb), expectedHip(h)) << i;
    HipPacket h2;
    ASSERT_EQ(decodeHip(hb, sizeof hb, h2), PacketError::None);
    ASSERT_EQ(std::memcmp(&h2.seq, &h.seq, 8), 0);
    ASSERT_EQ(std::bit_cast<uint64_t>(h2.senderTime), std::bit_cast<uint64_t>(h.senderTime));  // -0 stays -0
    for (int k = 0; k < 3; ++k)
      ASSERT_EQ(std::bit_cast<uint64_t>(h2.position[k]), std::bit_cast<uint64_t>(h.position[k]));
    ASSERT_EQ(h2.buttons, h.buttons);

    const ForcePacket f = randomForce();
    uint8_t fb[kForcePacketSize];
    encodeForce(f, fb);
    ASSERT_EQ(std::vector<uint8_t>(fb, fb + sizeof fb), expectedForce(f)) << i;
    ForcePacket f2;
    ASSERT_EQ(decodeForce(fb, sizeof fb, f2), PacketError::None);
    ASSERT_EQ(f2.seq, f.seq);
    ASSERT_EQ(std::bit_cast<uint64_t>(f2.loopTime), std::bit_cast<uint64_t>(f.loopTime));
    for (int k = 0; k < 3; ++k) ASSERT_EQ(std::bit_cast<uint64_t>(f2.force[k]), std::bit_cast<uint64_t>(f.force[k]));
    ASSERT_EQ(f2.status, f.status);
    ASSERT_EQ(f2.fault, f.fault);
  }
  // One packet spelled out byte by byte: seq 0x0102030405060708, time 1.5, (1, -2, 0.25), buttons 5.
  HipPacket h;
  h.seq = 0x0102030405060708ull;
  h.senderTime = 1.5;
  h.position[0] = 1;
  h.position[1] = -2;
  h.position[2] = 0.25;
  h.buttons = 5;
  uint8_t b[kHipPacketSize];
  encodeHip(h, b);
  const uint8_t want[56] = {'S', 'F', 'H', 'D', 1, 0, 1,    0,    8, 7, 6, 5, 4, 3, 2,    1,     // header, seq
                            0,   0,   0,   0,   0, 0, 0xF8, 0x3F, 0, 0, 0, 0, 0, 0, 0xF0, 0x3F,  // 1.5, 1.0
                            0,   0,   0,   0,   0, 0, 0,    0xC0, 0, 0, 0, 0, 0, 0, 0xD0, 0x3F,  // -2.0, 0.25
                            5,   0,   0,   0,   0, 0, 0,    0};                                  // buttons, reserved
  EXPECT_EQ(std::memcmp(b, want, 56), 0);
}

TEST_F(RuntimeUdpPacket, MalformedPacketsAreRejectedWithTheirReason) {
  uint8_t good[kHipPacketSize];
  encodeHip(randomHip(), good);
  HipPacket out;
  out.seq = 77;
  auto hip = [&](std::vector<uint8_t> b) { return decodeHip(b.data(), b.size(), out); };
  const std::vector<uint8_t> base(good, good + sizeof good);
  int checked = 0;
  for (size_t n = 0; n < 200; ++n) {  // every other length
    if (n == kHipPacketSize) continue;
    std::vector<uint8_t> b = base;
    b.resize(n, 0);
    ASSERT_EQ(hip(b), PacketError::Size) << n;
    ++checked;
  }
  for (int i = 0; i < 4; ++i) {
    std::vector<uint8_t> b = base;
    b[size_t(i)] ^= 0x20;
    EXPECT_EQ(hip(b), PacketError::Magic) << i;
    ++checked;
  }
  for (uint16_t v : {0, 2, 3, 256, 65535}) {
    for (size_t n : {size_t(8), kHipPacketSize, size_t(80)}) {  // another version may have another size
      std::vector<uint8_t> b = base;
      b.resize(n, 0);
      put<uint16_t>(b, 4, v);
      EXPECT_EQ(hip(b), PacketError::Version) << v << " " << n;
      ++checked;
    }
  }
  for (uint8_t t : {0, 2, 3, 255}) {
    std::vector<uint8_t> b = base;
    b[6] = t;
    EXPECT_EQ(hip(b), PacketError::Type) << int(t);
    ++checked;
  }
  for (size_t at : {size_t(7), size_t(52), size_t(55)}) {
    std::vector<uint8_t> b = base;
    b[at] = 1;
    EXPECT_EQ(hip(b), PacketError::Reserved) << at;
    ++checked;
  }
  for (size_t at : {size_t(16), size_t(24), size_t(32), size_t(40)}) {
    for (double bad : {NAN, INFINITY, -INFINITY}) {
      std::vector<uint8_t> b = base;
      put<double>(b, at, bad);
      EXPECT_EQ(hip(b), PacketError::NonFinite) << at;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 199 + 4 + 15 + 4 + 3 + 12);
  EXPECT_EQ(out.seq, 77u) << "a rejected packet must not be written out";
  // A FORCE packet is the wrong type for the HIP decoder and vice versa.
  uint8_t fb[kForcePacketSize];
  encodeForce(randomForce(), fb);
  EXPECT_EQ(decodeHip(fb, sizeof fb, out), PacketError::Type);
  ForcePacket f;
  EXPECT_EQ(decodeForce(good, sizeof good, f), PacketError::Type);
  // Random datagrams of random lengths: none decodes, none crashes.
  int accepted = 0;
  std::vector<uint8_t> r(128);
  for (int i = 0; i < 100000; ++i) {
    const size_t n = rng() % r.size();
    for (size_t k = 0; k < n; ++k) r[k] = uint8_t(rng());
    if (i % 2) std::memcpy(r.data(), "SFHD\x01\x00\x01\x00", std::min<size_t>(n, 8));  // half with a valid header
    accepted += decodeHip(r.data(), n, out) == PacketError::None;
  }
  // Accepted only with the exact size, zero reserved words and finite doubles: about 1 in
  // 128 * 2^32 random datagrams; none in this fixed-seed run.
  EXPECT_EQ(accepted, 0);
}

TEST(RuntimeUdpStatus, StepFlagsAndFaultsMapToTheWire) {
  ForceStatus s;
  EXPECT_EQ(udpStatusBits(s), 0u);
  s.contact = true;
  s.flags = kSafetyClamped | kSafetyRateLimited | kSafetyRamping | kSafetyMissedDeadline | kStepStale | kSafetyFaulted;
  EXPECT_EQ(udpStatusBits(s), 0x7Fu);
  s = {};
  s.fault = Fault::StaleDevice;
  EXPECT_EQ(udpStatusBits(s), uint32_t(kForceFaulted));
  EXPECT_EQ(udpFault(Fault::None), UdpFault::None);
  EXPECT_EQ(uint32_t(udpFault(Fault::NonFiniteHip)), 1u);
  EXPECT_EQ(uint32_t(udpFault(Fault::NonFiniteForce)), 2u);
  EXPECT_EQ(uint32_t(udpFault(Fault::MissedDeadlines)), 3u);
  EXPECT_EQ(uint32_t(udpFault(Fault::StaleDevice)), 4u);
}

}  // namespace
