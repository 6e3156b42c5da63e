// SPDX-License-Identifier: Apache-2.0
#include <smoothforce/runtime/udp_packet.h>

#include <bit>
#include <cmath>

#include <smoothforce/runtime/servo_step.h>

namespace sf::rt {
namespace {

void putU16(uint8_t* p, uint16_t v) noexcept {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
}
void putU32(uint8_t* p, uint32_t v) noexcept {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void putU64(uint8_t* p, uint64_t v) noexcept {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
void putF64(uint8_t* p, double v) noexcept { putU64(p, std::bit_cast<uint64_t>(v)); }
uint16_t getU16(const uint8_t* p) noexcept { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t getU32(const uint8_t* p) noexcept {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
uint64_t getU64(const uint8_t* p) noexcept {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
double getF64(const uint8_t* p) noexcept { return std::bit_cast<double>(getU64(p)); }

void putHeader(uint8_t* p, UdpPacketType type) noexcept {
  for (int i = 0; i < 4; ++i) p[i] = kUdpMagic[i];
  putU16(p + 4, kUdpVersion);
  p[6] = static_cast<uint8_t>(type);
  p[7] = 0;
}

/// The checks shared by both types, up to the exact size.
PacketError checkHeader(const uint8_t* d, size_t size, UdpPacketType type, size_t want) noexcept {
  if (size < kUdpHeaderSize) return PacketError::Size;
  for (int i = 0; i < 4; ++i)
    if (d[i] != kUdpMagic[i]) return PacketError::Magic;
  if (getU16(d + 4) != kUdpVersion) return PacketError::Version;
  if (d[6] != static_cast<uint8_t>(type)) return PacketError::Type;
  if (size != want) return PacketError::Size;
  if (d[7] != 0) return PacketError::Reserved;
  return PacketError::None;
}

}  // namespace

const char* toString(PacketError e) {
  switch (e) {
    case PacketError::None:
      return "ok";
    case PacketError::Size:
      return "wrong size";
    case PacketError::Magic:
      return "bad magic";
    case PacketError::Version:
      return "wrong version";
    case PacketError::Type:
      return "wrong type";
    case PacketError::Reserved:
      return "reserved field not zero";
    case PacketError::NonFinite:
      return "non-finite value";
  }
  return "?";
}

void encodeHip(const HipPacket& p, uint8_t out[kHipPacketSize]) noexcept {
  putHeader(out, UdpPacketType::Hip);
  putU64(out + 8, p.seq);
  putF64(out + 16, p.senderTime);
  for (int i = 0; i < 3; ++i) putF64(out + 24 + 8 * i, p.position[i]);
  putU32(out + 48, p.buttons);
  putU32(out + 52, 0);
}

void encodeForce(const ForcePacket& p, uint8_t out[kForcePacketSize]) noexcept {
  putHeader(out, UdpPacketType::Force);
  putU64(out + 8, p.seq);
  putF64(out + 16, p.senderTime);
  putF64(out + 24, p.loopTime);
  for (int i = 0; i < 3; ++i) putF64(out + 32 + 8 * i, p.force[i]);
  putU32(out + 56, p.status);
  putU32(out + 60, p.fault);
}

PacketError decodeHip(const uint8_t* d, size_t size, HipPacket& out) noexcept {
  const PacketError e = checkHeader(d, size, UdpPacketType::Hip, kHipPacketSize);
  if (e != PacketError::None) return e;
  if (getU32(d + 52) != 0) return PacketError::Reserved;
  HipPacket p;
  p.seq = getU64(d + 8);
  p.senderTime = getF64(d + 16);
  for (int i = 0; i < 3; ++i) p.position[i] = getF64(d + 24 + 8 * i);
  p.buttons = getU32(d + 48);
  if (!std::isfinite(p.senderTime) || !std::isfinite(p.position[0]) || !std::isfinite(p.position[1]) ||
      !std::isfinite(p.position[2]))
    return PacketError::NonFinite;
  out = p;
  return PacketError::None;
}

PacketError decodeForce(const uint8_t* d, size_t size, ForcePacket& out) noexcept {
  const PacketError e = checkHeader(d, size, UdpPacketType::Force, kForcePacketSize);
  if (e != PacketError::None) return e;
  ForcePacket p;
  p.seq = getU64(d + 8);
  p.senderTime = getF64(d + 16);
  p.loopTime = getF64(d + 24);
  for (int i = 0; i < 3; ++i) p.force[i] = getF64(d + 32 + 8 * i);
  p.status = getU32(d + 56);
  p.fault = getU32(d + 60);
  if (!std::isfinite(p.senderTime) || !std::isfinite(p.loopTime) || !std::isfinite(p.force[0]) ||
      !std::isfinite(p.force[1]) || !std::isfinite(p.force[2]))
    return PacketError::NonFinite;
  out = p;
  return PacketError::None;
}

UdpFault udpFault(Fault f) noexcept {
  switch (f) {
    case Fault::None:
      return UdpFault::None;
    case Fault::NonFiniteHip:
      return UdpFault::NonFiniteHip;
    case Fault::NonFiniteForce:
      return UdpFault::NonFiniteForce;
    case Fault::MissedDeadlines:
      return UdpFault::MissedDeadlines;
    case Fault::StaleDevice:
      return UdpFault::StaleDevice;
    case Fault::NonFiniteTime:
      return UdpFault::NonFiniteTime;
  }
  return UdpFault::None;
}

uint32_t udpStatusBits(const ForceStatus& s) noexcept {
  uint32_t b = 0;
  if (s.contact) b |= kForceContact;
  if ((s.flags & kSafetyFaulted) || s.fault != Fault::None) b |= kForceFaulted;
  if (s.flags & kSafetyClamped) b |= kForceClamped;
  if (s.flags & kSafetyRateLimited) b |= kForceRateLimited;
  if (s.flags & kSafetyRamping) b |= kForceRamping;
  if (s.flags & kSafetyMissedDeadline) b |= kForceMissedDeadline;
  if (s.flags & kStepStale) b |= kForceStale;
  return b;
}

}  // namespace sf::rt
