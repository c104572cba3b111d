"""An archive reader written from docs/archive.md alone (the oracle of test_phynjo_archive.sh):
records, both CRC-32s (zlib), the header's lines, the snapshots' sections.

    read_archive.py list FILE            step, time (repr) and offset of every snapshot, a line each
    read_archive.py world FILE STEP CSV  exit 0 when CSV (phynjo-archive extract) holds the world
                                         of the snapshot at STEP, every value bit for bit
"""
import struct
import sys
import zlib


def records(data):
    at = 0
    while at < len(data):
        if at + 20 > len(data):
            return  # a head cut short: the end
        magic, kind, length, head_crc = struct.unpack_from("<4sIQI", data, at)
        assert magic == b"PJAR", f"no PJAR at byte {at}"
        assert zlib.crc32(data[at:at + 16]) == head_crc, f"head checksum at byte {at}"
        if at + 20 + length + 4 > len(data):
            return  # a payload cut short
        payload = data[at + 20:at + 20 + length]
        (crc,) = struct.unpack_from("<I", data, at + 20 + length)
        assert zlib.crc32(payload) == crc, f"payload checksum at byte {at}"
        yield at, kind, payload
        at += 24 + length


def snapshot(payload):
    step, time, n = struct.unpack_from("<QdQ", payload, 0)
    at, sections = 24, {}
    for _ in range(n):
        (k,) = struct.unpack_from("<Q", payload, at)
        name = payload[at + 8:at + 8 + k].decode()
        at += 8 + k
        (k,) = struct.unpack_from("<Q", payload, at)
        sections[name] = payload[at + 8:at + 8 + k]
        at += 8 + k
    assert at == len(payload), "bytes after the sections"
    return step, time, sections


def main():
    data = open(sys.argv[2], "rb").read()
    recs = list(records(data))
    assert recs[0][1] == 1 and recs[0][2].decode().startswith("format 1\n"), "the header first"
    header = dict(line.split(" ", 1) for line in recs[0][2].decode().splitlines()[1:])
    snaps = [(at,) + snapshot(p) for at, kind, p in recs[1:] if kind == 2]
    if sys.argv[1] == "list":
        for at, step, time, _ in snaps:
            print(step, repr(time), at)
        return 0
    step = int(sys.argv[3])
    at, _, time, sections = next(s for s in snaps if s[1] == step)
    world = sections["world"]
    fields, components, t, tick = struct.unpack_from("<QQdQ", world, 0)
    values = struct.unpack_from(f"<{fields * components}d", world, 32)
    names = header.get("world.fields", "").split(",")
    lines = open(sys.argv[4]).read().splitlines()
    want_head = ["t", "tick", "component"] + (names if len(names) == fields else [f"field{f}" for f in range(fields)])
    assert lines[0].split(",") == want_head, f"the CSV's header {lines[0]!r}, not {want_head}"
    assert len(lines) == components + 1, f"{len(lines) - 1} rows for {components} components"
    for i, line in enumerate(lines[1:]):
        cells = line.split(",")
        assert float(cells[0]) == t and int(cells[1]) == tick and int(cells[2]) == i, f"row {i}: {cells[:3]}"
        for f in range(fields):
            got, want = float(cells[3 + f]), values[f * components + i]
            assert struct.pack("<d", got) == struct.pack("<d", want), f"row {i}, {want_head[3 + f]}: {got!r} is not {want!r}"
    print(f"the world at step {step}: {components} components x {fields} fields, bit for bit")
    return 0


if __name__ == "__main__":
    sys.exit(main())
