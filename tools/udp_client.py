#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Plays a HIP trajectory to `smoothforce loop --device udp:...` and records the forces.

Standard library only. Reads a CSV trajectory `t,x,y,z` (seconds, metres in the device
frame; an optional header line, blank lines and lines starting with '#' are skipped; times
strictly increasing), samples it at --rate Hz with linear interpolation (the first and last
positions held outside it), and sends one HIP packet per sample (protocol version 1, see
docs/guide.md "Real devices: the network bridge"). Meanwhile it receives the loop's FORCE packets
and writes them to --out as CSV:

    seq,sent_t,recv_t,x,y,z,loop_t,fx,fy,fz,status,fault

seq: the HIP sample the force was computed from (echoed by the loop); sent_t and recv_t:
when that sample was sent and when this force arrived, s on this client's clock; x,y,z: that
sample's position (m, device frame); loop_t: the loop's time, s; fx,fy,fz: N, device frame;
status and fault: as in the packet. A summary goes to stdout. Exit status 0, or 1 with one
line on stderr for bad input.

Example:
    smoothforce loop --cache out/spot.sfcache --device udp:127.0.0.1:5555 --duration 30 &
    python3 tools/udp_client.py --port 5555 --trajectory traj.csv --out forces.csv
"""

import argparse
import csv
import math
import socket
import struct
import sys
import time

MAGIC = b"SFHD"
VERSION = 1
TYPE_HIP = 1
TYPE_FORCE = 2
# Little-endian, no padding: header (magic, version u16, type u8, reserved u8), then the body.
HIP = struct.Struct("<4sHBBQddddII")  # seq, sender time, x, y, z, buttons, reserved: 56 bytes
FORCE = struct.Struct("<4sHBBQdddddII")  # seq, sender time echo, loop time, fx, fy, fz, status, fault: 64
assert HIP.size == 56 and FORCE.size == 64

STATUS_BITS = {
    "contact": 1 << 0,
    "faulted": 1 << 1,
    "clamped": 1 << 2,
    "rate_limited": 1 << 3,
    "ramping": 1 << 4,
    "missed_deadline": 1 << 5,
    "stale": 1 << 6,
}
FAULTS = {0: "none", 1: "non-finite HIP", 2: "non-finite force", 3: "missed deadlines", 4: "stale device",
          5: "non-finite step time"}


class InputError(Exception):
    pass


def encode_hip(seq, sender_time, x, y, z, buttons=0):
    return HIP.pack(MAGIC, VERSION, TYPE_HIP, 0, seq, sender_time, x, y, z, buttons, 0)


def decode_force(data):
    """The FORCE packet's fields as a dict, or None when `data` is not a valid version-1 FORCE packet."""
    if len(data) != FORCE.size:
        return None
    magic, version, ptype, reserved, seq, sent, loop_t, fx, fy, fz, status, fault = FORCE.unpack(data)
    if magic != MAGIC or version != VERSION or ptype != TYPE_FORCE or reserved != 0:
        return None
    if not all(math.isfinite(v) for v in (sent, loop_t, fx, fy, fz)):
        return None
    return {"seq": seq, "sender_time": sent, "loop_time": loop_t, "force": (fx, fy, fz), "status": status,
            "fault": fault}


def read_trajectory(path):
    """Rows (t, x, y, z) of a CSV trajectory; InputError naming path:line on bad input."""
    rows = []
    try:
        f = open(path, newline="")
    except OSError as e:
        raise InputError(f"{path}: cannot open: {e.strerror}")
    with f:
        for line_no, line in enumerate(f, 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cols = [c.strip() for c in s.split(",")]
            if not rows and cols == ["t", "x", "y", "z"]:
                continue
            if len(cols) != 4:
                raise InputError(f"{path}:{line_no}: expected 4 columns t,x,y,z, got {len(cols)}")
            try:
                vals = [float(c) for c in cols]
            except ValueError:
                raise InputError(f"{path}:{line_no}: not a number in '{s}'")
            if not all(math.isfinite(v) for v in vals):
                raise InputError(f"{path}:{line_no}: non-finite value in '{s}'")
            if rows and not vals[0] > rows[-1][0]:
                raise InputError(f"{path}:{line_no}: time {vals[0]:g} s is not greater than the previous row's")
            rows.append(tuple(vals))
    if not rows:
        raise InputError(f"{path}: no rows")
    return rows


def position_at(rows, t, cursor):
    """Linear interpolation at time t (rows' times, s since the start); cursor: the last segment used."""
    if t <= rows[0][0]:
        return rows[0][1:], cursor
    if t >= rows[-1][0]:
        return rows[-1][1:], cursor
    while rows[cursor + 1][0] < t:
        cursor += 1
    (t0, *p0), (t1, *p1) = rows[cursor], rows[cursor + 1]
    u = (t - t0) / (t1 - t0)
    return tuple(a + u * (b - a) for a, b in zip(p0, p1)), cursor


def percentile(values, p):
    if not values:
        return float("nan")
    v = sorted(values)
    return v[max(0, min(len(v) - 1, math.ceil(p / 100 * len(v)) - 1))]


def run(args):
    rows = read_trajectory(args.trajectory)
    t_start_traj = rows[0][0]
    rows = [(t - t_start_traj, x, y, z) for t, x, y, z in rows]
    length = rows[-1][0] if args.duration is None else args.duration
    period = 1.0 / args.rate
    count = int(math.floor(length * args.rate + 1e-9)) + 1

    family = socket.AF_INET6 if ":" in args.host else socket.AF_INET
    bind = args.bind or ("::1" if family == socket.AF_INET6 else "127.0.0.1")
    sock = socket.socket(family, socket.SOCK_DGRAM)
    try:
        sock.bind((bind, 0))
    except OSError as e:
        raise InputError(f"--bind {bind}: {e.strerror}")
    sock.setblocking(False)
    target = (args.host, args.port)

    sent = {}  # seq -> (sent_t, x, y, z)
    forces = []
    malformed = 0

    def drain():
        nonlocal malformed
        while True:
            try:
                data = sock.recv(2048)
            except (BlockingIOError, InterruptedError):
                return
            except OSError:  # e.g. ICMP port unreachable before the loop listens
                return
            f = decode_force(data)
            if f is None:
                malformed += 1
                continue
            forces.append((f, time.monotonic() - t0))

    t0 = time.monotonic()
    cursor = 0
    send_errors = 0
    for k in range(count):
        due = t0 + k * period
        while True:
            now = time.monotonic()
            if now >= due:
                break
            drain()
            time.sleep(min(due - now, 0.0005))
        t = k * period
        p, cursor = position_at(rows, t, cursor)
        seq = args.first_seq + k
        now = time.monotonic() - t0
        try:
            sock.sendto(encode_hip(seq, now, *p), target)
        except OSError:
            send_errors += 1
        sent[seq] = (now, *p)
        drain()
    end = time.monotonic() + args.linger
    while time.monotonic() < end:
        drain()
        time.sleep(0.001)
    drain()
    sock.close()

    rtts = []
    try:
        out = open(args.out, "w", newline="")
    except OSError as e:
        raise InputError(f"{args.out}: cannot open for writing: {e.strerror}")
    with out:
        w = csv.writer(out, lineterminator="\n")
        w.writerow(["seq", "sent_t", "recv_t", "x", "y", "z", "loop_t", "fx", "fy", "fz", "status", "fault"])
        for f, recv_t in forces:
            s = sent.get(f["seq"])
            if s is None:
                malformed += 1  # an echo of a sample this client never sent
                continue
            rtts.append(recv_t - s[0])
            w.writerow([f["seq"], f"{s[0]:.9f}", f"{recv_t:.9f}", repr(s[1]), repr(s[2]), repr(s[3]),
                        f"{f['loop_time']:.9f}", repr(f["force"][0]), repr(f["force"][1]), repr(f["force"][2]),
                        f["status"], f["fault"]])
    faults = sorted({f["fault"] for f, _ in forces if f["fault"]})
    print(f"sent {count} HIP samples at {args.rate:g} Hz over {length:g} s ({send_errors} send errors); "
          f"received {len(forces)} forces ({malformed} malformed or unknown), "
          f"round trip p50 {percentile(rtts, 50) * 1e3:.3f} ms, p99 {percentile(rtts, 99) * 1e3:.3f} ms; "
          f"faults: {', '.join(FAULTS.get(x, str(x)) for x in faults) or 'none'}")
    print(f"forces: {args.out}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--host", default="127.0.0.1", help="the loop's address (default 127.0.0.1)")
    ap.add_argument("--port", type=int, required=True, help="the loop's UDP port")
    ap.add_argument("--bind", help="local address to send from (default 127.0.0.1, or ::1 for an IPv6 host)")
    ap.add_argument("--trajectory", required=True, help="CSV t,x,y,z (s, m, device frame)")
    ap.add_argument("--rate", type=float, default=1000.0, help="samples per second (default 1000)")
    ap.add_argument("--duration", type=float, help="seconds to play (default: the trajectory's length)")
    ap.add_argument("--first-seq", type=int, default=1, help="sequence number of the first sample (default 1)")
    ap.add_argument("--linger", type=float, default=0.2, help="seconds to keep receiving after the last sample")
    ap.add_argument("--out", required=True, help="CSV of the forces received")
    args = ap.parse_args(argv)
    try:
        if not (0 < args.port < 65536):
            raise InputError(f"--port: expected 1..65535, got {args.port}")
        if not (args.rate > 0 and math.isfinite(args.rate) and args.rate <= 20000):
            raise InputError(f"--rate: expected 0 < rate <= 20000 Hz, got {args.rate:g}")
        if args.duration is not None and not (args.duration >= 0 and math.isfinite(args.duration)):
            raise InputError(f"--duration: expected a finite time >= 0 s, got {args.duration:g}")
        if not (0 <= args.first_seq < 2**63):
            raise InputError(f"--first-seq: expected 0 .. 2^63-1, got {args.first_seq}")
        if not (args.linger >= 0 and math.isfinite(args.linger)):
            raise InputError(f"--linger: expected a finite time >= 0 s, got {args.linger:g}")
        run(args)
    except InputError as e:
        print(f"udp_client: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
