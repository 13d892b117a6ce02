"""Rewrite a lem_fracture checkpoint with one value changed and valid
checksums, for the tests that a checkpoint is checked beyond its checksums.

Usage: craft_checkpoint.py SOURCE TARGET CASE      (--list: the cases)

The layout (src/protocol/checkpoint.cpp, version 6): the head -- 8 magic
bytes, the length of the rest of the head as u64, the state (its size as
u64, then its bytes), the fingerprint (u64 length, text), the damage
history (bond events, bond batches, node events, node batches, builds: each
u64 count then int64 values), the value counts of the displacement and of
the check field (u64 each; 0 for no check field), the number of columns of
the learnt deflation space (u64), the 64-bit FNV-1a checksum of all of it
-- then the displacement, the check field and each column of the learnt
space by node id (doubles, as many as the displacement each), then the
order-free checksum of those values: the sum modulo 2**64 of
mix64(mix64(k) ^ bits) over value k of all of them in that order.
"""
import argparse
import struct
import sys

VECTORS = ("bond_events", "bond_batches", "node_events", "node_batches", "build_batches")
MASK = 0xFFFFFFFFFFFFFFFF


def fnv1a(data):
    h = 1469598103934665603
    for byte in data:
        h = ((h ^ byte) * 1099511628211) & MASK
    return h


def mix64(x):
    x = (x + 0x9E3779B97F4A7C15) & MASK
    x = ((x ^ (x >> 30)) * 0xBF58476D1CE4E5B9) & MASK
    x = ((x ^ (x >> 27)) * 0x94D049BB133111EB) & MASK
    return x ^ (x >> 31)


def field_checksum(values):
    total = 0
    for k, v in enumerate(values):
        bits = struct.unpack("<Q", struct.pack("<d", v))[0]
        total = (total + mix64(mix64(k) ^ bits)) & MASK
    return total


def parse(data):
    pos = 8
    c = {"magic": data[:8]}

    def u64():
        nonlocal pos
        value = struct.unpack_from("<Q", data, pos)[0]
        pos += 8
        return value

    body = u64()
    head_end = pos + body
    size = u64()
    c["state"] = data[pos:pos + size]
    pos += size
    n = u64()
    c["fingerprint"] = data[pos:pos + n]
    pos += n
    n = u64()
    c["relaxation_state"] = data[pos:pos + n]
    pos += n
    for name in VECTORS:
        n = u64()
        c[name] = list(struct.unpack_from("<%dq" % n, data, pos))
        pos += 8 * n
    counts = u64(), u64()
    columns = u64()
    if pos != head_end or u64() != fnv1a(data[:head_end]):
        raise SystemExit("not a checkpoint of this layout (or its head checksum is wrong)")
    for name, n in zip(("displacement", "check_displacement"), counts):
        c[name] = list(struct.unpack_from("<%dd" % n, data, pos))
        pos += 8 * n
    c["space"] = []
    for _ in range(columns):
        c["space"].append(list(struct.unpack_from("<%dd" % counts[0], data, pos)))
        pos += 8 * counts[0]
    if pos + 8 != len(data) or u64() != field_checksum(fields(c)):
        raise SystemExit("not a checkpoint of this layout (or its field checksum is wrong)")
    return c


def fields(c):
    """Every field value in the order of the file."""
    return c["displacement"] + c["check_displacement"] + [v for w in c["space"] for v in w]


def build(c):
    body = struct.pack("<Q", len(c["state"])) + c["state"]
    body += struct.pack("<Q", len(c["fingerprint"])) + c["fingerprint"]
    body += struct.pack("<Q", len(c["relaxation_state"])) + c["relaxation_state"]
    for name in VECTORS:
        body += struct.pack("<Q%dq" % len(c[name]), len(c[name]), *c[name])
    body += struct.pack("<QQQ", len(c["displacement"]), len(c["check_displacement"]),
                        len(c["space"]))
    out = bytearray(c["magic"]) + struct.pack("<Q", len(body)) + body
    out += struct.pack("<Q", fnv1a(out))
    values = fields(c)
    out += struct.pack("<%dd" % len(values), *values)
    out += struct.pack("<Q", field_checksum(values))
    return bytes(out)


def nodes(c):
    for line in c["fingerprint"].decode().splitlines():
        if line.startswith("nodes="):
            return int(line[6:])
    raise SystemExit("no nodes= line in the fingerprint")


def short_displacement(c):
    del c["displacement"][-3:]


def nan_displacement(c):
    c["displacement"][5] = float("nan")


def short_check_field(c):
    c["check_displacement"] = c["displacement"][:-3]


def bond_not_in_sample(c):
    c["bond_events"][2] = 10 ** 9


def bond_broken_twice(c):
    c["bond_events"][2] = c["bond_events"][1]


def node_out_of_range(c):
    c["node_events"].append(nodes(c) + 5)
    c["node_batches"].append(c["bond_batches"][-1])


def batch_beyond_state(c):
    c["bond_batches"][-1] = 10 ** 6


def space_too_wide(c):
    c["space"] = [[0.0] * len(c["displacement"]) for _ in range(65)]


def nan_in_space(c):
    c["space"] = [[1.0] * len(c["displacement"])]
    c["space"][0][7] = float("inf")


CASES = {f.__name__: f for f in (short_displacement, nan_displacement, short_check_field,
                                  bond_not_in_sample,
                                  bond_broken_twice, node_out_of_range, batch_beyond_state,
                                  space_too_wide, nan_in_space)}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("source", nargs="?")
    parser.add_argument("target", nargs="?")
    parser.add_argument("case", nargs="?", choices=sorted(CASES) + ["unchanged"])
    parser.add_argument("--list", action="store_true", help="print the cases and stop")
    args = parser.parse_args(argv)
    if args.list:
        print("\n".join(sorted(CASES)))
        return 0
    if not (args.source and args.target and args.case):
        parser.error("SOURCE, TARGET and CASE are required")
    with open(args.source, "rb") as f:
        data = f.read()
    c = parse(data)
    if build(c) != data:
        raise SystemExit("the rewrite of an unchanged checkpoint differs: layout misread")
    if args.case != "unchanged":
        CASES[args.case](c)
    with open(args.target, "wb") as f:
        f.write(build(c))
    return 0


if __name__ == "__main__":
    sys.exit(main())
