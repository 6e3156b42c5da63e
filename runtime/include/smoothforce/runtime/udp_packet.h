// SPDX-License-Identifier: Apache-2.0
// The network bridge's packet format, version 1: HIP packets in, FORCE packets out.
// Little-endian, serialised byte by byte (no struct is sent as it lies in memory).
#pragma once

#include <cstddef>
#include <cstdint>

#include <smoothforce/runtime/device.h>

namespace sf::rt {

/// Every packet starts with this 8-byte header:
///   0  4 bytes  magic "SFHD" (0x53 0x46 0x48 0x44)
///   4  u16      version (kUdpVersion)
///   6  u8       type (UdpPacketType)
///   7  u8       reserved, 0
/// HIP packet (type 1, sender -> loop), exactly kHipPacketSize = 56 bytes:
///   8  u64 seq (strictly increasing per sender; a restart: UdpDevice), 16 f64 sender time (s, sender's clock),
///   24 f64 x, 32 f64 y, 40 f64 z (m, device frame), 48 u32 buttons, 52 u32 reserved 0.
/// FORCE packet (type 2, loop -> the sender of the samples), exactly kForcePacketSize = 64:
///   8  u64 seq (echo of the HIP sample this force was computed from),
///   16 f64 sender time (echo of that sample's), 24 f64 loop time (s since the loop start),
///   32 f64 fx, 40 f64 fy, 48 f64 fz (N, device frame), 56 u32 status (kForce* bits),
///   60 u32 fault (UdpFault).
/// Integers are unsigned little-endian, reals IEEE-754 binary64 little-endian.
inline constexpr uint8_t kUdpMagic[4] = {'S', 'F', 'H', 'D'};
inline constexpr uint16_t kUdpVersion = 1;
inline constexpr size_t kUdpHeaderSize = 8;
inline constexpr size_t kHipPacketSize = 56;
inline constexpr size_t kForcePacketSize = 64;

enum class UdpPacketType : uint8_t { Hip = 1, Force = 2 };

/// FORCE packet status bits.
enum UdpForceStatus : uint32_t {
  kForceContact = 1u << 0,         ///< the renderer reported contact
  kForceFaulted = 1u << 1,         ///< a fault is latched: the force is zero (see the fault field)
  kForceClamped = 1u << 2,         ///< |F| was clamped to the force limit
  kForceRateLimited = 1u << 3,     ///< the force change was limited
  kForceRamping = 1u << 4,         ///< inside the ramp-in after the start
  kForceMissedDeadline = 1u << 5,  ///< the step ended after its deadline
  kForceStale = 1u << 6,           ///< the watchdog expired (no fresh HIP sample)
};

/// FORCE packet fault codes (the wire values are fixed; Fault may grow).
enum class UdpFault : uint32_t {
  None = 0,
  NonFiniteHip = 1,
  NonFiniteForce = 2,
  MissedDeadlines = 3,
  StaleDevice = 4,
  NonFiniteTime = 5  ///< not sent by `loop` (its own clock); for completeness
};

struct HipPacket {
  uint64_t seq = 0;
  double senderTime = 0;           ///< s
  double position[3] = {0, 0, 0};  ///< m, device frame
  uint32_t buttons = 0;
};

struct ForcePacket {
  uint64_t seq = 0;
  double senderTime = 0;        ///< s, echoed
  double loopTime = 0;          ///< s since the loop start
  double force[3] = {0, 0, 0};  ///< N, device frame
  uint32_t status = 0;          ///< UdpForceStatus bits
  uint32_t fault = 0;           ///< UdpFault
};

/// Why a datagram was dropped.
enum class PacketError : uint8_t {
  None,
  Size,       ///< shorter than the header, or not the exact size of its type
  Magic,      ///< does not start with "SFHD"
  Version,    ///< another version (the size is not checked then)
  Type,       ///< not the type expected here
  Reserved,   ///< a reserved field is not zero
  NonFinite,  ///< a time or coordinate is NaN or infinite
};
const char* toString(PacketError e);

void encodeHip(const HipPacket& p, uint8_t out[kHipPacketSize]) noexcept;
void encodeForce(const ForcePacket& p, uint8_t out[kForcePacketSize]) noexcept;
/// Checks, in order: size >= header, magic, version, type, exact size, reserved, finite.
/// `out` is written only when the result is PacketError::None.
PacketError decodeHip(const uint8_t* data, size_t size, HipPacket& out) noexcept;
PacketError decodeForce(const uint8_t* data, size_t size, ForcePacket& out) noexcept;

/// The FORCE status bits and fault code for a step's ForceStatus.
uint32_t udpStatusBits(const ForceStatus& s) noexcept;
UdpFault udpFault(Fault f) noexcept;

}  // namespace sf::rt
