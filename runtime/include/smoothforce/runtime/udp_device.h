// SPDX-License-Identifier: Apache-2.0
// `udp:[HOST:]PORT`: a haptic device in another process, over UDP (the network bridge).
#pragma once

#include <sys/socket.h>

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

#include <smoothforce/runtime/device.h>
#include <smoothforce/runtime/seqlock.h>
#include <smoothforce/runtime/udp_packet.h>

namespace sf::rt {

/// Where the loop listens.
struct UdpEndpoint {
  std::string host = "127.0.0.1";  ///< local address to bind (a name or numeric IPv4/IPv6; 0.0.0.0: all)
  int port = 0;                    ///< 0: any free port (describe() names the one bound)
};

/// Parses "udp:PORT", "udp:HOST:PORT" or "udp:[IPv6]:PORT" (HOST defaults to 127.0.0.1: only
/// this machine can send unless another address is given). Throws InputError
/// ("--device udp:[HOST:]PORT: ...") for anything else or a port outside 0..65535.
UdpEndpoint parseUdpSpec(const std::string& spec);

/// Options of the UDP device. Units: seconds.
struct UdpOptions {
  double watchdog = 0.05;  ///< no fresh sample for this long: read() reports Stale (> 0, finite)
  /// Resynchronisation: this many valid packets from the sender in a row with a seq below the
  /// last accepted one, each above the one before it, and the last of them is accepted as a
  /// new start (UdpDevice). >= 2: a late packet alone is always dropped.
  int resyncAfter = 8;
};

/// Counts since construction (a snapshot; every datagram lands in exactly one of accepted,
/// duplicates, outOfOrder, foreign, wrongVersion or one malformed kind).
struct UdpCounters {
  int64_t received = 0;    ///< datagrams (counted after each one's verdict below)
  int64_t accepted = 0;    ///< valid HIP samples published to the loop
  int64_t duplicates = 0;  ///< seq equal to the last accepted one
  int64_t outOfOrder = 0;  ///< seq below the last accepted one (late, reordered) and not a resynchronisation
  int64_t resyncs = 0;     ///< of the accepted: resynchronisations (a restarted sender, a seq jump; UdpDevice)
  int64_t foreign = 0;     ///< valid, but from another address than the first sender
  int64_t wrongVersion = 0;
  int64_t badSize = 0, badMagic = 0, badType = 0, badReserved = 0, nonFinite = 0;  ///< malformed
  int64_t outOfRange = 0;  ///< malformed: a coordinate beyond the coordinate range (+-1e15 m, coordinate_range.h)
  int64_t superseded = 0;  ///< accepted but never read: a newer sample arrived first
  int64_t forcesSent = 0, sendErrors = 0;
  int64_t malformed() const noexcept { return badSize + badMagic + badType + badReserved + nonFinite + outOfRange; }
};

/// Receives HIP packets (udp_packet.h) on a socket bound to the endpoint and sends FORCE
/// packets back to the sender of the samples.
///
/// A receiver thread decodes every datagram and drops, counting each kind, malformed ones
/// (size, magic, type, reserved bits, NaN/inf, a coordinate beyond +-1e15 m: no position the
/// queries take), other versions, duplicates and out-of-order
/// packets (seq not above the last accepted one; seq must increase within a run) and packets
/// from any address but the first valid sender's (one device, one sender).
/// Resynchronisation: a sender that restarts from a low seq, or one whose seq jumped far ahead
/// once (to 2^64-1, say), would otherwise have every later packet dropped as out of order, and
/// the watchdog would latch a stale fault. When `resyncAfter` (8) valid packets from the sender
/// arrive in a row with a seq below the last accepted one, each above the one before it in
/// that run, the sender is taken to have started again: the last of them is accepted (counted
/// in `accepted` and in `resyncs`) and its seq is the one later packets must exceed; the ones
/// before it are counted out of order. An accepted packet, a duplicate of the last accepted
/// seq, or one not above its predecessor in the run starts the count again, so late packets
/// scattered among newer ones are always dropped; only a burst of `resyncAfter` late packets in
/// increasing order with nothing newer in between would be taken for a restart (one step on a
/// sample a few ms old, counted). A sender at R Hz recovers after resyncAfter / R s (8 ms at
/// 1 kHz), well inside the default watchdog (50 ms). An accepted
/// sample goes to a seqlock mailbox; read() takes the latest one without waiting (real-time
/// safe: no allocation, lock or blocking call). The watchdog: when the latest sample arrived
/// `watchdog` s or more before read(), read() reports DeviceStatus::Stale, and the servo step
/// latches Fault::StaleDevice (zero force, reported). Before the first sample read() reports
/// NoSample (nothing rendered, zero force, no fault).
/// commandForce() sends one FORCE packet per step, echoing the seq and sender time of the
/// sample read, with a non-blocking sendto from the calling thread (a syscall, no allocation
/// or lock in this process); nothing is sent before the first sample.
/// Device-paced: waitForSample() blocks on a futex until the receiver publishes a newer
/// sample, the timeout passes, or the watchdog of the latest sample expires; it returns true
/// only once it has taken that sample, so the read() after it renders it (a read that met the
/// receiver in the middle of its next write, preempted there, used to return the sample before
/// and the loop stepped on it twice).
class UdpDevice final : public HapticDevice {
 public:
  /// Binds the socket and starts the receiver thread. Throws InputError naming the endpoint
  /// when the address does not resolve or cannot be bound, or the watchdog is out of range.
  explicit UdpDevice(const UdpEndpoint& endpoint, const UdpOptions& options = {});
  ~UdpDevice() override;
  UdpDevice(const UdpDevice&) = delete;
  UdpDevice& operator=(const UdpDevice&) = delete;

  DeviceState read(double t) noexcept override;
  void writeForce(const Eigen::Vector3d& f) noexcept override;
  void commandForce(const Eigen::Vector3d& f, const ForceStatus& status) noexcept override;
  bool canPace() const noexcept override { return true; }
  bool waitForSample(double timeout) noexcept override;
  std::string describe() const override;
  std::string report() const override;

  /// The bound port (the one chosen by the system for port 0).
  int port() const noexcept { return port_; }
  UdpCounters counters() const noexcept;

 private:
  struct Sample {
    uint64_t seq;
    double senderTime;
    double position[3];
    uint32_t buttons;
    uint32_t pad;
    int64_t receivedNs;  ///< CLOCK_MONOTONIC
  };
  enum Counter : int {
    kReceived,
    kAccepted,
    kDuplicates,
    kOutOfOrder,
    kResyncs,
    kForeign,
    kWrongVersion,
    kBadSize,
    kBadMagic,
    kBadType,
    kBadReserved,
    kNonFinite,
    kOutOfRange,
    kSuperseded,
    kForcesSent,
    kSendErrors,
    kCounters
  };
  void receiveLoop() noexcept;
  void handle(const uint8_t* data, size_t size, const sockaddr_storage& from, socklen_t fromLen,
              int64_t receivedNs) noexcept;
  void count(Counter c, int64_t n = 1) noexcept { counters_[c].fetch_add(n, std::memory_order_relaxed); }

  std::string host_;
  int port_ = 0;
  double watchdog_;
  int resyncAfter_;
  int fd_ = -1;
  std::atomic<int64_t> counters_[kCounters] = {};
  // Receiver thread.
  std::atomic<bool> stop_{false};
  bool haveSeq_ = false;
  uint64_t lastSeq_ = 0;
  int behind_ = 0;           ///< packets in the current run below lastSeq_ (resynchronisation)
  uint64_t behindSeq_ = 0;   ///< the seq of the run's last packet
  sockaddr_storage peer_{};  ///< the first valid sender; written once, before peerSet_
  socklen_t peerLen_ = 0;
  std::atomic<bool> peerSet_{false};
  SeqlockMailbox<Sample> mailbox_;
  std::atomic<uint32_t> published_{0};  ///< futex word: bumped after each publish
  // Servo thread.
  /// Takes the mailbox's sample into latest_ where it is newer than the one taken (counting the
  /// ones it skipped as superseded, and the one it replaces when no read() returned it yet);
  /// false where there is none newer, or a write overlapped every attempt.
  bool takeNewer() noexcept;
  Sample latest_{};
  bool unread_ = false;  ///< latest_ was taken by waitForSample and no read() has returned it
  uint64_t readVersion_ = 0;
  std::thread thread_;
};

}  // namespace sf::rt
