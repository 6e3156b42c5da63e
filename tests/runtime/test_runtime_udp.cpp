// SPDX-License-Identifier: Apache-2.0
// The UDP device on the loopback address with a sender thread: samples and echoed forces,
// loss, reordering and duplicates, garbage, the watchdog when the sender stops (fixed-rate and
// device-paced loops), the device-paced step count, and a real-time read/write path.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <random>
#include <set>
#include <thread>
#include <vector>

#include <smoothforce/runtime/analytic_renderers.h>
#include <smoothforce/runtime/clock.h>
#include <smoothforce/runtime/servo_loop.h>
#include <smoothforce/runtime/udp_device.h>
#include "runtime_alloc_counter.h"

namespace {

using Eigen::Vector3d;
using namespace sf::rt;
using Clock_ = std::chrono::steady_clock;

/// Polls `done` every millisecond for at most `seconds`; true when it became true.
bool waitFor(const std::function<bool()>& done, double seconds) {
  const auto until = Clock_::now() + std::chrono::duration<double>(seconds);
  while (!done()) {
    if (Clock_::now() > until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

/// A UDP socket on the loopback address with a free port: the sender process stand-in.
class Peer {
 public:
  explicit Peer(int family = AF_INET) : family_(family) {
    fd = ::socket(family, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_storage a = address(0);
    ok = fd >= 0 && ::bind(fd, reinterpret_cast<sockaddr*>(&a), length()) == 0;
  }
  ~Peer() {
    if (fd >= 0) ::close(fd);
  }
  void send(int port, const void* data, size_t n) {
    sockaddr_storage a = address(port);
    ASSERT_EQ(::sendto(fd, data, n, 0, reinterpret_cast<sockaddr*>(&a), length()), ssize_t(n));
  }
  void sendHip(int port, uint64_t seq, const Vector3d& p, double t = 0, uint32_t buttons = 0) {
    HipPacket h;
    h.seq = seq;
    h.senderTime = t;
    for (int i = 0; i < 3; ++i) h.position[i] = p[i];
    h.buttons = buttons;
    uint8_t b[kHipPacketSize];
    encodeHip(h, b);
    send(port, b, sizeof b);
  }
  /// FORCE packets that arrived, without waiting; undecodable ones are counted in `bad`.
  void drain(std::vector<ForcePacket>& out) {
    uint8_t b[256];
    for (;;) {
      const ssize_t n = ::recv(fd, b, sizeof b, MSG_DONTWAIT);
      if (n < 0) return;
      ForcePacket f;
      if (decodeForce(b, size_t(n), f) == PacketError::None)
        out.push_back(f);
      else
        ++bad;
    }
  }
  int fd = -1;
  bool ok = false;
  int bad = 0;

 private:
  sockaddr_storage address(int port) const {
    sockaddr_storage s{};
    if (family_ == AF_INET) {
      auto& a = reinterpret_cast<sockaddr_in&>(s);
      a.sin_family = AF_INET;
      a.sin_port = htons(uint16_t(port));
      a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    } else {
      auto& a = reinterpret_cast<sockaddr_in6&>(s);
      a.sin6_family = AF_INET6;
      a.sin6_port = htons(uint16_t(port));
      a.sin6_addr = in6addr_loopback;
    }
    return s;
  }
  socklen_t length() const { return family_ == AF_INET ? sizeof(sockaddr_in) : sizeof(sockaddr_in6); }
  int family_;
};

SafetyOptions transparent() {
  SafetyOptions o;
  o.maxForce = 1e6;
  o.maxForceStep = INFINITY;
  o.rampTime = 0;
  o.maxConsecutiveMisses = 1 << 30;  // a loaded test machine misses deadlines; not under test here
  return o;
}

/// The plane z <= 0 that also publishes the x of the last HIP it saw (for the sender thread).
class WatchedPlane final : public sf::ForceRenderer {
 public:
  PlaneRenderer plane{Vector3d::UnitZ(), 0.0, 500.0};
  std::atomic<double> lastX{NAN};
  sf::ForceSample step(const Vector3d& hip) noexcept override {
    lastX.store(hip.x(), std::memory_order_relaxed);
    return plane.step(hip);
  }
  void reset() noexcept override {}
  int patchesBuilt() const noexcept override { return 0; }
};

std::vector<StepRecord> drain(SpscRing<StepRecord>& ring) {
  std::vector<StepRecord> v;
  for (StepRecord r; ring.tryPop(r);) v.push_back(r);
  return v;
}

TEST(RuntimeUdp, SpecsAndSetupErrors) {
  EXPECT_EQ(parseUdpSpec("udp:5555").host, "127.0.0.1");
  EXPECT_EQ(parseUdpSpec("udp:5555").port, 5555);
  EXPECT_EQ(parseUdpSpec("udp:0.0.0.0:0").host, "0.0.0.0");
  EXPECT_EQ(parseUdpSpec("udp:[::1]:6000").host, "::1");
  EXPECT_EQ(parseUdpSpec("udp:[::1]:6000").port, 6000);
  EXPECT_EQ(parseUdpSpec("udp:localhost:65535").port, 65535);
  int bad = 0;
  for (const char* s : {"udp:", "udp:65536", "udp:-1", "udp:12a", "udp::5", "udp:[::1]5", "udp:[::1]:", "udp:[]:5",
                        "tcp:5555", "udp:123456"}) {
    try {
      parseUdpSpec(s);
      ADD_FAILURE() << s << " accepted";
    } catch (const sf::InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--device udp:[HOST:]PORT: expected", 0), 0u) << e.what();
      ++bad;
    }
  }
  EXPECT_EQ(bad, 10);
  UdpDevice a(UdpEndpoint{"127.0.0.1", 0});
  EXPECT_GT(a.port(), 0);
  EXPECT_NE(a.describe().find("udp 127.0.0.1:" + std::to_string(a.port())), std::string::npos) << a.describe();
  try {
    UdpDevice b(UdpEndpoint{"127.0.0.1", a.port()});
    ADD_FAILURE() << "the port is taken";
  } catch (const sf::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("udp:127.0.0.1:" + std::to_string(a.port()) + ": cannot bind"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(UdpDevice(UdpEndpoint{"no-such-host.invalid", 0}), sf::InputError);
  UdpOptions o;
  o.watchdog = 0;
  EXPECT_THROW(UdpDevice(UdpEndpoint{}, o), sf::InputError);
}

TEST(RuntimeUdp, SampleInForceOutEchoesTheSample) {
  for (int family : {AF_INET, AF_INET6}) {
    const std::string host = family == AF_INET ? "127.0.0.1" : "::1";
    std::unique_ptr<UdpDevice> dev;
    try {
      dev = std::make_unique<UdpDevice>(UdpEndpoint{host, 0});
    } catch (const sf::InputError& e) {
      if (family == AF_INET6) {
        std::printf("IPv6 loopback unavailable, skipped: %s\n", e.what());
        continue;
      }
      throw;
    }
    Peer peer(family);
    ASSERT_TRUE(peer.ok);
    EXPECT_EQ(dev->read(0).status, DeviceStatus::NoSample);
    dev->commandForce(Vector3d(1, 2, 3), ForceStatus{});
    EXPECT_EQ(dev->counters().forcesSent, 0) << "nobody to send to before the first sample";
    peer.sendHip(dev->port(), 10, Vector3d(0.1, -0.2, 0.3), 0.5, 6);
    ASSERT_TRUE(waitFor([&] { return dev->counters().accepted == 1; }, 5));
    const DeviceState d = dev->read(0);
    EXPECT_EQ(d.status, DeviceStatus::Ok);
    EXPECT_EQ(d.position, Vector3d(0.1, -0.2, 0.3));
    EXPECT_EQ(d.buttons, 6u);
    EXPECT_EQ(d.sample, 10u);
    EXPECT_GE(d.age, 0);
    ForceStatus st;
    st.loopTime = 1.25;
    st.flags = kSafetyClamped;
    st.contact = true;
    dev->commandForce(Vector3d(0.5, -1.5, 2.5), st);
    std::vector<ForcePacket> got;
    ASSERT_TRUE(waitFor(
        [&] {
          peer.drain(got);
          return !got.empty();
        },
        5));
    ASSERT_EQ(got.size(), 1u);
    EXPECT_EQ(got[0].seq, 10u);
    EXPECT_EQ(got[0].senderTime, 0.5);
    EXPECT_EQ(got[0].loopTime, 1.25);
    EXPECT_EQ(Vector3d(got[0].force[0], got[0].force[1], got[0].force[2]), Vector3d(0.5, -1.5, 2.5));
    EXPECT_EQ(got[0].status, uint32_t(kForceContact | kForceClamped));
    EXPECT_EQ(got[0].fault, 0u);
    EXPECT_EQ(dev->counters().forcesSent, 1);
  }
}

// Sent in this order: seqs 1..600 with every seq = 3 (mod 7) lost, every seq = 0 (mod 11) sent
// twice, every pair (s, s + 1) with s = 1 (mod 10) swapped, and seq 5 sent again after every
// 100th. The expected counts come from replaying that order against "accept only a seq above
// the last accepted". A device-paced loop runs meanwhile: it must step only on accepted
// samples, in increasing order, and every FORCE packet must echo one with its force.
TEST(RuntimeUdp, LossReorderingAndDuplicatesAreDropped) {
  std::vector<uint64_t> order;
  for (uint64_t s = 1; s <= 600; ++s) {
    if (s % 10 == 1 && s + 1 <= 600) {
      for (uint64_t q : {s + 1, s})
        if (q % 7 != 3) order.push_back(q);
      ++s;
    } else if (s % 7 != 3) {
      order.push_back(s);
    }
    if (s % 11 == 0 && s % 7 != 3) order.push_back(s);
    if (s % 100 == 0) order.push_back(5);
  }
  std::set<uint64_t> accepted;
  int64_t dups = 0, late = 0;
  uint64_t maxSeq = 0;
  for (uint64_t s : order) {
    if (!accepted.empty() && s == maxSeq) {
      ++dups;
    } else if (!accepted.empty() && s < maxSeq) {
      ++late;
    } else {
      accepted.insert(s);
      maxSeq = s;
    }
  }
  ASSERT_GT(dups, 40);
  ASSERT_GT(late, 40);
  auto pos = [](uint64_t s) { return Vector3d(1e-4 * double(s), -2e-4 * double(s), -0.002 + 1e-5 * double(s % 17)); };

  UdpOptions uo;
  uo.watchdog = 10;  // not under test here
  UdpDevice dev(UdpEndpoint{"127.0.0.1", 0}, uo);
  WatchedPlane plane;
  SafetyFilter safety(transparent());
  SpscRing<StepRecord> ring(4096);
  FastForwardClock clock;
  std::atomic<bool> stop{false};
  LoopOptions lo;
  lo.devicePaced = true;
  lo.duration = 30;  // bounded; the sender stops the loop when done
  lo.stop = &stop;
  ServoLoop loop(dev, plane, safety, clock, lo, &ring);

  Peer peer;
  ASSERT_TRUE(peer.ok);
  std::vector<ForcePacket> forces;
  bool flowOk = true, consumed = false;
  std::thread sender([&] {
    for (size_t i = 0; i < order.size(); ++i) {
      peer.sendHip(dev.port(), order[i], pos(order[i]), double(i) * 1e-3);
      if (i % 40 == 39 || i + 1 == order.size()) {  // flow control: the socket buffer never overflows
        flowOk = flowOk && waitFor([&] { return dev.counters().received == int64_t(i + 1); }, 10);
        peer.drain(forces);
      }
    }
    consumed = waitFor([&] { return plane.lastX.load() == pos(maxSeq).x(); }, 10);
    stop.store(true);
  });
  loop.run();
  sender.join();
  ASSERT_TRUE(flowOk);
  ASSERT_TRUE(consumed) << "the loop never stepped on the last sample";

  const UdpCounters c = dev.counters();
  EXPECT_EQ(c.received, int64_t(order.size()));
  EXPECT_EQ(c.accepted, int64_t(accepted.size()));
  EXPECT_EQ(c.duplicates, dups);
  EXPECT_EQ(c.outOfOrder, late);
  EXPECT_EQ(c.resyncs, 0);
  EXPECT_EQ(c.malformed() + c.wrongVersion + c.foreign, 0);
  const std::vector<StepRecord> recs = drain(ring);
  const LoopStats& st = loop.stats();
  EXPECT_TRUE(st.paced);
  ASSERT_EQ(int64_t(recs.size()), st.steps);
  EXPECT_EQ(st.steps + c.superseded, c.accepted) << "one step per sample read";
  uint64_t prev = 0;
  for (const StepRecord& r : recs) {
    ASSERT_GT(r.sample, prev);
    prev = r.sample;
    ASSERT_TRUE(accepted.count(r.sample)) << r.sample;
    ASSERT_EQ(Vector3d(r.hip[0], r.hip[1], r.hip[2]), pos(r.sample));
    ASSERT_EQ(r.flags & (uint32_t(kStepStale) | kSafetyFaulted), 0u);
  }
  ASSERT_TRUE(waitFor(
      [&] {
        peer.drain(forces);
        return int64_t(forces.size()) == c.forcesSent;
      },
      5));
  EXPECT_EQ(c.forcesSent, st.steps);
  uint64_t last = 0;
  for (const ForcePacket& f : forces) {
    ASSERT_GE(f.seq, last);
    last = f.seq;
    ASSERT_TRUE(accepted.count(f.seq)) << f.seq;
    const Vector3d want = 500 * std::max(0.0, -pos(f.seq).z()) * Vector3d::UnitZ();
    ASSERT_EQ(Vector3d(f.force[0], f.force[1], f.force[2]), want) << f.seq;
    ASSERT_EQ(f.status & kForceContact, want.z() > 0 ? uint32_t(kForceContact) : 0u);
  }
  EXPECT_EQ(peer.bad, 0);
}

// Every kind of bad datagram, interleaved with valid samples, from the sender and from a second
// socket: each is counted in its category, none reaches the loop.
// A sender whose seq jumps far ahead once (to 2^64-1, 2^62) or that restarts from 1 had every
// later packet dropped as out of order: the watchdog latched a stale fault, zero force until
// restart. Each sequence below is sent whole to a device; the counts are worked out by hand
// from the rule (8 packets in a row below the last accepted one, each above the one before
// it: the 8th is accepted as a new start) and the device must end on the sequence's last seq.
// Late packets, alone, in bursts of 7, in bursts of 8 that decrease, or among newer ones, are
// still all dropped.
TEST(RuntimeUdp, SeqJumpsAndSenderRestartsResynchroniseAfterEightPackets) {
  struct Case {
    const char* name;
    std::vector<uint64_t> seqs;
    int64_t accepted, duplicates, outOfOrder, resyncs;
    uint64_t last;  ///< seq of the latest accepted sample
  };
  auto range = [](std::vector<uint64_t>& v, uint64_t from, uint64_t to) {
    for (uint64_t s = from; s <= to; ++s) v.push_back(s);
  };
  std::vector<Case> cases;
  {  // 1..100, 2^64-1, 101..400: 101..107 dropped, 108 resynchronises, 109..400 follow
    Case c{"jump to 2^64-1", {}, 100 + 1 + 1 + 292, 0, 7, 1, 400};
    range(c.seqs, 1, 100);
    c.seqs.push_back(UINT64_MAX);
    range(c.seqs, 101, 400);
    cases.push_back(c);
  }
  {
    Case c{"jump to 2^62", {}, 100 + 1 + 1 + 292, 0, 7, 1, 400};
    range(c.seqs, 1, 100);
    c.seqs.push_back(uint64_t(1) << 62);
    range(c.seqs, 101, 400);
    cases.push_back(c);
  }
  {  // the sender restarts from 1 after 500 packets
    Case c{"restart", {}, 500 + 1 + 292, 0, 7, 1, 300};
    range(c.seqs, 1, 500);
    range(c.seqs, 1, 300);
    cases.push_back(c);
  }
  {  // two restarts, the second from 0
    Case c{"two restarts", {}, 200 + 2 * (1 + 92), 0, 14, 2, 99};
    range(c.seqs, 1, 200);
    range(c.seqs, 1, 100);
    range(c.seqs, 0, 99);
    cases.push_back(c);
  }
  {  // after the jump, 103 arrives late among 101..114: the run starts again at 103, 108..114
     // make it 8 long; then a duplicate of the last seq
    Case c{"reordered after the jump", {}, 100 + 1 + 1 + 86, 1, 7 + 1 + 6, 1, 200};
    range(c.seqs, 1, 100);
    c.seqs.push_back(UINT64_MAX);
    range(c.seqs, 101, 107);
    c.seqs.push_back(103);
    range(c.seqs, 108, 200);
    c.seqs.push_back(200);  // a duplicate of the last one
    cases.push_back(c);
  }
  {  // a duplicate of 2^64-1 within the run starts the count again: 101..104, dup, 105..111
     // dropped, 112 resynchronises
    Case c{"duplicate in the run", {}, 100 + 1 + 1 + 88, 1, 4 + 7, 1, 200};
    range(c.seqs, 1, 100);
    c.seqs.push_back(UINT64_MAX);
    range(c.seqs, 101, 104);
    c.seqs.push_back(UINT64_MAX);
    range(c.seqs, 105, 200);
    cases.push_back(c);
  }
  {  // every 50th packet is followed by 8 late ones in decreasing order, then by 7 increasing:
     // all 15 x 20 dropped, no resynchronisation
    Case c{"late bursts", {}, 1000, 0, 20 * 15, 0, 1000};
    for (uint64_t s = 1; s <= 1000; ++s) {
      c.seqs.push_back(s);
      if (s % 50 == 0) {
        for (uint64_t q = s - 1; q >= s - 8; --q) c.seqs.push_back(q);
        range(c.seqs, s - 20, s - 14);
      }
    }
    cases.push_back(c);
  }
  {  // a late packet after every new one (the previous seq but one): 499 dropped
    Case c{"late among newer", {}, 501, 0, 499, 0, 501};
    c.seqs.push_back(1);
    for (uint64_t s = 2; s <= 501; ++s) {
      c.seqs.push_back(s);
      if (s >= 3) c.seqs.push_back(s - 2);
    }
    cases.push_back(c);
  }
  int checked = 0;
  for (const Case& k : cases) {
    SCOPED_TRACE(k.name);
    ASSERT_EQ(k.accepted + k.duplicates + k.outOfOrder, int64_t(k.seqs.size())) << "the case's counts";
    UdpOptions uo;
    uo.watchdog = 10;  // not under test here
    UdpDevice dev(UdpEndpoint{"127.0.0.1", 0}, uo);
    Peer peer;
    ASSERT_TRUE(peer.ok);
    for (size_t i = 0; i < k.seqs.size(); ++i) {
      peer.sendHip(dev.port(), k.seqs[i], Vector3d(1e-4 * double(i), 0, 0));
      if (i % 40 == 39 || i + 1 == k.seqs.size()) {  // flow control: the socket buffer never overflows
        ASSERT_TRUE(waitFor([&] { return dev.counters().received == int64_t(i + 1); }, 10));
      }
    }
    const UdpCounters c = dev.counters();
    EXPECT_EQ(c.received, int64_t(k.seqs.size()));
    EXPECT_EQ(c.accepted, k.accepted);
    EXPECT_EQ(c.duplicates, k.duplicates);
    EXPECT_EQ(c.outOfOrder, k.outOfOrder);
    EXPECT_EQ(c.resyncs, k.resyncs);
    EXPECT_EQ(c.malformed() + c.wrongVersion + c.foreign, 0);
    const DeviceState d = dev.read(0);
    EXPECT_EQ(d.status, DeviceStatus::Ok);
    EXPECT_EQ(d.sample, k.last);
    EXPECT_NE(dev.report().find(std::to_string(k.resyncs) + " seq resynchronisations"), std::string::npos)
        << dev.report();
    ++checked;
  }
  EXPECT_EQ(checked, 8);
  UdpOptions o;
  o.resyncAfter = 1;  // a single late packet would be accepted
  EXPECT_THROW(UdpDevice(UdpEndpoint{}, o), sf::InputError);
}

TEST(RuntimeUdp, GarbageIsCountedAndDropped) {
  UdpDevice dev(UdpEndpoint{"127.0.0.1", 0});
  Peer peer, other;
  ASSERT_TRUE(peer.ok && other.ok);
  uint8_t good[kHipPacketSize];
  auto valid = [&](uint64_t seq) {
    HipPacket h;
    h.seq = seq;
    h.position[0] = double(seq);
    encodeHip(h, good);
    return std::vector<uint8_t>(good, good + sizeof good);
  };
  std::mt19937_64 rng(3);
  int64_t want[6] = {};  // size, magic, version, type, reserved, non-finite
  int64_t sent = 0, validSent = 0, foreign = 0;
  uint64_t seq = 0;
  for (int round = 0; round < 60; ++round) {
    peer.send(dev.port(), valid(++seq).data(), kHipPacketSize);
    ++validSent;
    std::vector<uint8_t> b = valid(seq + 1000);  // corrupted copies of a future seq: never accepted
    switch (round % 8) {
      case 0:
        b.resize(size_t(rng() % kHipPacketSize));
        ++want[0];
        break;
      case 1:
        b.push_back(0);
        ++want[0];
        break;
      case 2:
        b[rng() % 4] ^= 0x41;
        ++want[1];
        break;
      case 3:
        b[4] = 2;  // version 2
        ++want[2];
        break;
      case 4:
        b[6] = 2;  // a FORCE packet's type
        ++want[3];
        break;
      case 5:
        b[53] = 9;
        ++want[4];
        break;
      case 6: {
        const double nan = NAN;
        std::memcpy(b.data() + 24 + 8 * (rng() % 3), &nan, 8);  // a NaN coordinate (little-endian host)
        ++want[5];
        break;
      }
      case 7:  // valid, but from another socket: the first sender owns the device
        other.send(dev.port(), b.data(), b.size());
        ++foreign;
        ++sent;
        continue;
    }
    if (round % 16 == 0) {  // and a datagram larger than the receive buffer
      std::vector<uint8_t> big(4000, 0x53);
      peer.send(dev.port(), big.data(), big.size());
      ++want[0];
      ++sent;
    }
    peer.send(dev.port(), b.data(), b.size());
    ++sent;
    ASSERT_TRUE(waitFor([&] { return dev.counters().received == sent + validSent; }, 5));
  }
  const UdpCounters c = dev.counters();
  EXPECT_EQ(c.accepted, validSent);
  EXPECT_EQ(c.badSize, want[0]);
  EXPECT_EQ(c.badMagic, want[1]);
  EXPECT_EQ(c.wrongVersion, want[2]);
  EXPECT_EQ(c.badType, want[3]);
  EXPECT_EQ(c.badReserved, want[4]);
  EXPECT_EQ(c.nonFinite, want[5]);
  EXPECT_EQ(c.foreign, foreign);
  EXPECT_EQ(c.received, sent + validSent);
  const DeviceState d = dev.read(0);
  EXPECT_EQ(d.sample, seq);
  EXPECT_EQ(d.position.x(), double(seq));
  EXPECT_NE(dev.report().find("60 samples accepted"), std::string::npos) << dev.report();
}

// A HIP beyond the coordinate range (+-1e15 m) is no position the queries take: it was counted
// as accepted (1e300 m included). It is dropped and counted as malformed (out of range), like
// a NaN one; the next valid sample is taken as usual.
TEST(RuntimeUdp, HipsBeyondTheCoordinateRangeAreDropped) {
  UdpDevice dev(UdpEndpoint{"127.0.0.1", 0});
  Peer peer;
  ASSERT_TRUE(peer.ok);
  uint64_t seq = 0;
  int64_t sent = 0, far = 0, accepted = 0;
  for (const double x : {1e300, -1e300, 1e16, 1.0000001e15, -1.0000001e15, 1e15, -1e15, 1e14, 0.25}) {
    for (int axis = 0; axis < 3; ++axis) {
      Vector3d p(0.1, 0.2, 0.3);
      p[axis] = x;
      peer.sendHip(dev.port(), ++seq, p);
      ++sent;
      const bool beyond = std::abs(x) > 1e15;
      far += beyond;
      accepted += !beyond;
      ASSERT_TRUE(waitFor([&] { return dev.counters().received == sent; }, 5));
      const DeviceState d = dev.read(0);
      if (!beyond) {
        EXPECT_EQ(d.sample, seq);
        EXPECT_EQ(d.position[axis], x);
      }
    }
  }
  const UdpCounters c = dev.counters();
  EXPECT_EQ(far, 15);
  EXPECT_EQ(c.outOfRange, far);
  EXPECT_EQ(c.malformed(), far);
  EXPECT_EQ(c.accepted, accepted);
  EXPECT_EQ(dev.read(0).position, Vector3d(0.1, 0.2, 0.25));
  EXPECT_NE(dev.report().find("non-finite 0, beyond 1e15 m 15)"), std::string::npos) << dev.report();
}

/// Sends `n` samples `period` s apart (p(k) 1 mm deep), then stops.
void playSamples(Peer& peer, int port, int n, double period) {
  const auto t0 = Clock_::now();
  for (int k = 1; k <= n; ++k) {
    std::this_thread::sleep_until(t0 + std::chrono::duration<double>(period * k));
    peer.sendHip(port, uint64_t(k), Vector3d(1e-5 * k, 0, -0.001), period * k);
  }
}

/// The records after the sender stopped: the first step that read a sample at least `watchdog`
/// old latched the stale fault; no step before it was faulted, every step from it on commanded
/// zero force.
void expectStaleFaultAtExpiry(const std::vector<StepRecord>& recs, double watchdog, uint64_t lastSample) {
  size_t f = 0;
  while (f < recs.size() && !(recs[f].flags & kStepStale)) ++f;
  ASSERT_LT(f, recs.size()) << "no stale step";
  ASSERT_GT(f, 0u);
  EXPECT_GE(recs[f].age, watchdog);
  EXPECT_LT(recs[f - 1].age, watchdog);
  EXPECT_EQ(recs[f].sample, lastSample);
  for (size_t i = 0; i < f; ++i) ASSERT_EQ(recs[i].flags & kSafetyFaulted, 0u) << i;
  for (size_t i = f; i < recs.size(); ++i) {
    ASSERT_TRUE(recs[i].flags & kSafetyFaulted) << i;
    ASSERT_EQ(Vector3d(recs[i].force[0], recs[i].force[1], recs[i].force[2]), Vector3d::Zero()) << i;
  }
  std::printf("stale fault: sample age %.2f ms at the first stale step (watchdog %.0f ms), %.2f ms before it\n",
              recs[f].age * 1e3, watchdog * 1e3, recs[f - 1].age * 1e3);
}

TEST(RuntimeUdp, SenderStoppedFixedRateLoopZeroesTheForceAtTheWatchdog) {
  UdpOptions uo;
  uo.watchdog = 0.2;  // long enough that a loaded machine does not stall the sender past it
  UdpDevice dev(UdpEndpoint{"127.0.0.1", 0}, uo);
  Peer peer;
  ASSERT_TRUE(peer.ok);
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  SafetyFilter safety(transparent());
  SpscRing<StepRecord> ring(2048);
  SteadyClock clock(0);
  LoopOptions lo;
  lo.duration = 0.6;
  ServoLoop loop(dev, plane, safety, clock, lo, &ring);
  std::thread sender([&] { playSamples(peer, dev.port(), 150, 1e-3); });
  loop.run();
  sender.join();
  EXPECT_EQ(safety.counters().fault, Fault::StaleDevice);
  EXPECT_EQ(dev.counters().accepted, 150);
  const std::vector<StepRecord> recs = drain(ring);
  ASSERT_EQ(int64_t(recs.size()), loop.stats().steps);
  size_t first = 0;  // steps before the first sample render nothing
  while (first < recs.size() && (recs[first].flags & kStepNoSample)) ++first;
  ASSERT_LT(first, recs.size());
  EXPECT_TRUE(recs[first].contact);
  expectStaleFaultAtExpiry(std::vector<StepRecord>(recs.begin() + long(first), recs.end()), uo.watchdog, 150);
  EXPECT_EQ(loop.stats().ticks, 600);
}

// Device-paced: one step per sample (the sample numbers of the steps only increase), the
// samples not stepped on counted as superseded, and after the sender stops the wait ends at
// the watchdog and latches the fault.
TEST(RuntimeUdp, PacedLoopStepsOncePerSampleAndFaultsWhenTheSenderStops) {
  UdpOptions uo;
  uo.watchdog = 0.2;  // long enough that a loaded machine does not stall the sender past it
  UdpDevice dev(UdpEndpoint{"127.0.0.1", 0}, uo);
  Peer peer;
  ASSERT_TRUE(peer.ok);
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  SafetyFilter safety(transparent());
  SpscRing<StepRecord> ring(2048);
  SteadyClock clock(0);
  LoopOptions lo;
  lo.devicePaced = true;
  lo.rate = 500;
  lo.duration = 1.2;
  ServoLoop loop(dev, plane, safety, clock, lo, &ring);
  std::thread sender([&] { playSamples(peer, dev.port(), 300, 2e-3); });
  loop.run();
  sender.join();
  const UdpCounters c = dev.counters();
  EXPECT_EQ(c.accepted, 300);
  const std::vector<StepRecord> recs = drain(ring);
  ASSERT_EQ(int64_t(recs.size()), loop.stats().steps);
  int64_t fresh = 0;
  uint64_t prev = 0;
  for (const StepRecord& r : recs) {
    if (r.flags & kStepStale) continue;
    ASSERT_GT(r.sample, prev) << "a paced step without a new sample";
    prev = r.sample;
    ++fresh;
  }
  EXPECT_EQ(fresh + c.superseded, c.accepted);
  EXPECT_GE(fresh, c.accepted / 2) << "most samples should get their own step";
  EXPECT_LT(loop.stats().steps, 300 + 1.2 / 0.05 + 2) << "no steps without samples but the stale ones";
  EXPECT_EQ(safety.counters().fault, Fault::StaleDevice);
  expectStaleFaultAtExpiry(recs, uo.watchdog, 300);
  EXPECT_TRUE(loop.stats().paced);
  EXPECT_EQ(loop.stats().ticks, loop.stats().steps);
}

TEST(RuntimeUdp, PacedLoopNeedsADeviceThatPaces) {
  NullDevice d;
  PlaneRenderer plane(Vector3d::UnitZ(), 0.0, 500.0);
  SafetyFilter safety;
  FakeClock clock;
  LoopOptions lo;
  lo.devicePaced = true;
  EXPECT_THROW(ServoLoop(d, plane, safety, clock, lo), sf::InputError);
}

TEST(RuntimeUdp, ReadAndCommandDoNotAllocate) {
  if (!SF_COUNT_ALLOCS) GTEST_SKIP() << "allocation counting is off under sanitizers";
  UdpOptions uo;
  uo.watchdog = 100;
  UdpDevice dev(UdpEndpoint{"127.0.0.1", 0}, uo);
  Peer peer;
  ASSERT_TRUE(peer.ok);
  peer.sendHip(dev.port(), 1, Vector3d(0, 0, -0.001));
  ASSERT_TRUE(waitFor([&] { return dev.counters().accepted == 1; }, 5));
  sf::test::tAllocs = 0;
  sf::test::tCountAllocs = true;
  int ok = 0;
  for (int k = 0; k < 1000; ++k) {
    ok += dev.read(k * 1e-3).status == DeviceStatus::Ok;
    dev.commandForce(Vector3d(0, 0, 0.5), ForceStatus{});
    dev.waitForSample(0);
  }
  sf::test::tCountAllocs = false;
  EXPECT_EQ(sf::test::tAllocs, 0);
  EXPECT_EQ(ok, 1000);
  EXPECT_EQ(dev.counters().forcesSent + dev.counters().sendErrors, 1000);
}

}  // namespace
