// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/udp_device.h>

#include <linux/futex.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>

#include <smoothforce/base/coordinate_range.h>
#include <smoothforce/mesh/mesh.h>

namespace sf::rt {
namespace {

static_assert(sizeof(std::atomic<uint32_t>) == sizeof(uint32_t) && std::atomic<uint32_t>::is_always_lock_free,
              "the futex word is an atomic uint32_t");

int64_t monotonicNs() noexcept {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000LL + ts.tv_nsec;
}

/// Waits while *word == expected, at most `ns` nanoseconds (or until woken, or spuriously).
void futexWait(std::atomic<uint32_t>& word, uint32_t expected, int64_t ns) noexcept {
  timespec ts;
  ts.tv_sec = static_cast<time_t>(ns / 1000000000LL);
  ts.tv_nsec = static_cast<long>(ns % 1000000000LL);
  syscall(SYS_futex, reinterpret_cast<uint32_t*>(&word), FUTEX_WAIT_PRIVATE, expected, &ts, nullptr, 0);
}

void futexWakeAll(std::atomic<uint32_t>& word) noexcept {
  syscall(SYS_futex, reinterpret_cast<uint32_t*>(&word), FUTEX_WAKE_PRIVATE, 1 << 30, nullptr, nullptr, 0);
}

bool sameAddress(const sockaddr_storage& a, const sockaddr_storage& b) noexcept {
  if (a.ss_family != b.ss_family) return false;
  if (a.ss_family == AF_INET) {
    const auto& x = reinterpret_cast<const sockaddr_in&>(a);
    const auto& y = reinterpret_cast<const sockaddr_in&>(b);
    return x.sin_port == y.sin_port && x.sin_addr.s_addr == y.sin_addr.s_addr;
  }
  if (a.ss_family == AF_INET6) {
    const auto& x = reinterpret_cast<const sockaddr_in6&>(a);
    const auto& y = reinterpret_cast<const sockaddr_in6&>(b);
    return x.sin6_port == y.sin6_port && std::memcmp(&x.sin6_addr, &y.sin6_addr, sizeof x.sin6_addr) == 0;
  }
  return false;
}

std::string endpointName(const std::string& host, int port) {
  const bool v6 = host.find(':') != std::string::npos;
  return (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

}  // namespace

UdpEndpoint parseUdpSpec(const std::string& spec) {
  const std::string bad =
      "--device udp:[HOST:]PORT: expected udp:PORT, udp:HOST:PORT or udp:[IPv6]:PORT with PORT in "
      "0..65535 (0: any free port), got '" +
      spec + "'";
  if (spec.rfind("udp:", 0) != 0) throw InputError(bad);
  const std::string rest = spec.substr(4);
  UdpEndpoint e;
  std::string port;
  if (!rest.empty() && rest[0] == '[') {
    const size_t close = rest.find(']');
    if (close == std::string::npos || close == 1 || close + 1 >= rest.size() || rest[close + 1] != ':')
      throw InputError(bad);
    e.host = rest.substr(1, close - 1);
    port = rest.substr(close + 2);
  } else {
    const size_t colon = rest.rfind(':');
    if (colon == std::string::npos) {
      port = rest;
    } else {
      e.host = rest.substr(0, colon);
      port = rest.substr(colon + 1);
      if (e.host.empty()) throw InputError(bad);
    }
  }
  if (port.empty() || port.size() > 5 || port.find_first_not_of("0123456789") != std::string::npos)
    throw InputError(bad);
  e.port = std::stoi(port);
  if (e.port > 65535) throw InputError(bad);
  return e;
}

UdpDevice::UdpDevice(const UdpEndpoint& endpoint, const UdpOptions& options)
    : host_(endpoint.host), port_(endpoint.port), watchdog_(options.watchdog), resyncAfter_(options.resyncAfter) {
  const std::string name = "udp:" + endpointName(host_, port_);
  if (!(watchdog_ > 0) || !std::isfinite(watchdog_)) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", watchdog_ * 1e3);
    throw InputError(std::string("--watchdog-ms: expected a finite time > 0 ms, got ") + buf);
  }
  if (resyncAfter_ < 2)
    throw InputError(name + ": resyncAfter: expected at least 2 packets, got " + std::to_string(resyncAfter_));
  if (port_ < 0 || port_ > 65535) throw InputError(name + ": port outside 0..65535");
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  hints.ai_flags = AI_PASSIVE | AI_NUMERICSERV;
  addrinfo* res = nullptr;
  const std::string portStr = std::to_string(port_);
  const int gai = getaddrinfo(host_.c_str(), portStr.c_str(), &hints, &res);
  if (gai != 0) throw InputError(name + ": cannot resolve '" + host_ + "': " + gai_strerror(gai));
  int err = 0;
  for (addrinfo* a = res; a && fd_ < 0; a = a->ai_next) {
    const int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) {
      err = errno;
      continue;
    }
    if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0) {
      err = errno;
      ::close(fd);
      continue;
    }
    fd_ = fd;
  }
  freeaddrinfo(res);
  if (fd_ < 0) throw InputError(name + ": cannot bind: " + std::strerror(err));
  const int rcvbuf = 1 << 20;  // room for bursts; the kernel caps it at net.core.rmem_max
  setsockopt(fd_, SOL_SOCKET, SO_RCVBUF, &rcvbuf, sizeof rcvbuf);
  sockaddr_storage local{};
  socklen_t len = sizeof local;
  if (getsockname(fd_, reinterpret_cast<sockaddr*>(&local), &len) == 0) {
    if (local.ss_family == AF_INET) port_ = ntohs(reinterpret_cast<sockaddr_in&>(local).sin_port);
    if (local.ss_family == AF_INET6) port_ = ntohs(reinterpret_cast<sockaddr_in6&>(local).sin6_port);
  }
  thread_ = std::thread([this] { receiveLoop(); });
}

UdpDevice::~UdpDevice() {
  stop_.store(true, std::memory_order_relaxed);
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) ::close(fd_);
}

void UdpDevice::receiveLoop() noexcept {
  uint8_t buf[2048];
  while (!stop_.load(std::memory_order_relaxed)) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 20) <= 0) continue;  // 20 ms: how long the destructor may wait
    for (;;) {
      sockaddr_storage from{};
      socklen_t fromLen = sizeof from;
      const ssize_t n =
          ::recvfrom(fd_, buf, sizeof buf, MSG_DONTWAIT | MSG_TRUNC, reinterpret_cast<sockaddr*>(&from), &fromLen);
      if (n < 0) break;  // drained (EAGAIN) or an error: back to poll
      const int64_t recvNs = monotonicNs();
      if (static_cast<size_t>(n) > sizeof buf)
        count(kBadSize);  // longer than any packet: truncated by the kernel, MSG_TRUNC gave its length
      else
        handle(buf, static_cast<size_t>(n), from, fromLen, recvNs);
      // counted after the datagram's verdict: a reader that sees `received` n (counters(),
      // acquire) sees the verdicts of those n (waiting on `received`, a test read one short)
      counters_[kReceived].fetch_add(1, std::memory_order_release);
    }
  }
}

void UdpDevice::handle(const uint8_t* data, size_t size, const sockaddr_storage& from, socklen_t fromLen,
                       int64_t recvNs) noexcept {
  HipPacket p;
  switch (decodeHip(data, size, p)) {
    case PacketError::None:
      break;
    case PacketError::Size:
      return count(kBadSize);
    case PacketError::Magic:
      return count(kBadMagic);
    case PacketError::Version:
      return count(kWrongVersion);
    case PacketError::Type:
      return count(kBadType);
    case PacketError::Reserved:
      return count(kBadReserved);
    case PacketError::NonFinite:
      return count(kNonFinite);
  }
  if (!inCoordinateRange(p.position)) return count(kOutOfRange);  // 1e300 m was accepted as a HIP
  if (peerSet_.load(std::memory_order_relaxed) && !sameAddress(from, peer_)) return count(kForeign);
  if (haveSeq_ && p.seq == lastSeq_) {
    behind_ = 0;
    return count(kDuplicates);
  }
  if (haveSeq_ && p.seq < lastSeq_) {  // late, or a new start: resyncAfter_ in a row, increasing
    behind_ = behind_ > 0 && p.seq > behindSeq_ ? behind_ + 1 : 1;
    behindSeq_ = p.seq;
    if (behind_ < resyncAfter_) return count(kOutOfOrder);
    count(kResyncs);
  }
  behind_ = 0;
  if (!peerSet_.load(std::memory_order_relaxed)) {
    peer_ = from;
    peerLen_ = fromLen;
    peerSet_.store(true, std::memory_order_release);
  }
  haveSeq_ = true;
  lastSeq_ = p.seq;
  Sample s{};
  s.seq = p.seq;
  s.senderTime = p.senderTime;
  for (int i = 0; i < 3; ++i) s.position[i] = p.position[i];
  s.buttons = p.buttons;
  s.receivedNs = recvNs;
  mailbox_.tryWrite(s);  // the only writer: always succeeds
  count(kAccepted);
  published_.fetch_add(1, std::memory_order_release);
  futexWakeAll(published_);
}

bool UdpDevice::takeNewer() noexcept {
  if (mailbox_.version() == readVersion_) return false;
  Sample s;
  uint64_t v = 0;
  if (!mailbox_.read(s, v) || v <= readVersion_) return false;
  const int64_t skipped = static_cast<int64_t>(v - readVersion_ - 1) + (unread_ ? 1 : 0);
  if (skipped > 0) count(kSuperseded, skipped);
  latest_ = s;
  readVersion_ = v;
  return true;
}

DeviceState UdpDevice::read(double) noexcept {
  takeNewer();
  unread_ = false;
  DeviceState d;
  if (readVersion_ == 0) {
    d.status = DeviceStatus::NoSample;
    return d;
  }
  d.position = Eigen::Vector3d(latest_.position[0], latest_.position[1], latest_.position[2]);
  d.buttons = latest_.buttons;
  d.sample = latest_.seq;
  d.age = static_cast<double>(monotonicNs() - latest_.receivedNs) * 1e-9;
  d.status = d.age >= watchdog_ ? DeviceStatus::Stale : DeviceStatus::Ok;
  return d;
}

bool UdpDevice::waitForSample(double timeout) noexcept {
  const int64_t start = monotonicNs();
  int64_t deadline = start + static_cast<int64_t>(std::max(0.0, timeout) * 1e9);
  if (readVersion_ > 0) {
    const int64_t expiry = latest_.receivedNs + static_cast<int64_t>(watchdog_ * 1e9);
    if (expiry > start) deadline = std::min(deadline, expiry);
  }
  for (;;) {
    const uint32_t seen = published_.load(std::memory_order_acquire);
    // a newer sample taken; where a write overlapped the reads, the futex word has moved (or
    // moves when that write completes), so the wait below returns at once or then
    if (takeNewer()) return unread_ = true;
    const int64_t left = deadline - monotonicNs();
    if (left <= 0) return false;
    futexWait(published_, seen, left);
  }
}

void UdpDevice::writeForce(const Eigen::Vector3d& f) noexcept { commandForce(f, ForceStatus{}); }

void UdpDevice::commandForce(const Eigen::Vector3d& f, const ForceStatus& status) noexcept {
  if (readVersion_ == 0 || !peerSet_.load(std::memory_order_acquire)) return;
  ForcePacket p;
  p.seq = latest_.seq;
  p.senderTime = latest_.senderTime;
  p.loopTime = status.loopTime;
  for (int i = 0; i < 3; ++i) p.force[i] = f[i];
  p.status = udpStatusBits(status);
  p.fault = static_cast<uint32_t>(udpFault(status.fault));
  uint8_t buf[kForcePacketSize];
  encodeForce(p, buf);
  const ssize_t n =
      ::sendto(fd_, buf, sizeof buf, MSG_DONTWAIT | MSG_NOSIGNAL, reinterpret_cast<const sockaddr*>(&peer_), peerLen_);
  count(n == static_cast<ssize_t>(sizeof buf) ? kForcesSent : kSendErrors);
}

UdpCounters UdpDevice::counters() const noexcept {
  auto g = [this](Counter c) { return counters_[c].load(std::memory_order_relaxed); };
  UdpCounters c;
  c.received = counters_[kReceived].load(std::memory_order_acquire);  // first: the verdicts of these
  c.accepted = g(kAccepted);
  c.duplicates = g(kDuplicates);
  c.outOfOrder = g(kOutOfOrder);
  c.resyncs = g(kResyncs);
  c.foreign = g(kForeign);
  c.wrongVersion = g(kWrongVersion);
  c.badSize = g(kBadSize);
  c.badMagic = g(kBadMagic);
  c.badType = g(kBadType);
  c.badReserved = g(kBadReserved);
  c.nonFinite = g(kNonFinite);
  c.outOfRange = g(kOutOfRange);
  c.superseded = g(kSuperseded);
  c.forcesSent = g(kForcesSent);
  c.sendErrors = g(kSendErrors);
  return c;
}

std::string UdpDevice::describe() const {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                " (HIP packets in, FORCE packets back to the first sender; protocol v%d; watchdog %g ms)", kUdpVersion,
                watchdog_ * 1e3);
  return "udp " + endpointName(host_, port_) + buf;
}

std::string UdpDevice::report() const {
  const UdpCounters c = counters();
  char buf[640];
  std::snprintf(buf, sizeof buf,
                "udp: %lld datagrams, %lld samples accepted (%lld superseded before a read, %lld seq "
                "resynchronisations), %lld duplicates, %lld out of order, %lld from other senders, %lld wrong "
                "version, %lld malformed (size %lld, magic %lld, type %lld, reserved %lld, non-finite %lld, beyond "
                "1e15 m %lld); %lld forces sent, %lld send errors\n",
                (long long)c.received, (long long)c.accepted, (long long)c.superseded, (long long)c.resyncs,
                (long long)c.duplicates, (long long)c.outOfOrder, (long long)c.foreign, (long long)c.wrongVersion,
                (long long)c.malformed(), (long long)c.badSize, (long long)c.badMagic, (long long)c.badType,
                (long long)c.badReserved, (long long)c.nonFinite, (long long)c.outOfRange, (long long)c.forcesSent,
                (long long)c.sendErrors);
  return buf;
}

}  // namespace sf::rt
