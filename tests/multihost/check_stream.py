#!/usr/bin/env python3
"""Checks a /sample?interval stream of the multihost test.

usage: check_stream.py STREAM REQUESTER_LOG...

Every part's observations must carry consecutive sequence numbers, starting
where the previous part's nextSequence said. The requester's own transitions
(STATE lines of each log, after the READY it starts in) must appear in the
stream's values of machine-1's MaterialLoad request, in the same order.
Prints the number of transitions missing from the stream (0 when all are
there); exits 1 with a message on a sequence gap or an unreadable stream.
"""
import re
import sys
import xml.etree.ElementTree as ET


def parts(text):
    return re.findall(r"<\?xml.*?</MTConnectStreams>", text, re.S)


def local(tag):
    return tag.rsplit("}", 1)[-1]


def check(stream_path, logs):
    with open(stream_path, encoding="utf-8", errors="replace") as f:
        docs = parts(f.read())
    if not docs:
        sys.exit("no stream part received")
    expected_next = None
    values = []
    for n, doc in enumerate(docs):
        root = ET.fromstring(doc)
        header = next(e for e in root.iter() if local(e.tag) == "Header")
        seqs = []
        for device in (e for e in root.iter() if local(e.tag) == "DeviceStream"):
            for obs in device.iter():
                if "sequence" not in obs.attrib:
                    continue
                seq = int(obs.attrib["sequence"])
                seqs.append(seq)
                item = obs.attrib.get("dataItemId", "")
                if device.attrib.get("uuid") == "machine-1" and item.endswith("request"):
                    values.append((seq, (obs.text or "").strip()))
        seqs.sort()
        if seqs:
            start = seqs[0]
            if expected_next is not None and start != expected_next:
                sys.exit(f"part {n}: starts at {start}, previous nextSequence {expected_next}")
            if seqs != list(range(start, start + len(seqs))):
                sys.exit(f"part {n}: sequence numbers not consecutive: {seqs}")
        expected_next = int(header.attrib["nextSequence"])
    values.sort()
    seen = [v for _, v in values if v != "UNAVAILABLE"]
    want = []
    for log in logs:
        want.append("READY")
        with open(log, encoding="utf-8") as f:
            want += [line.split()[1] for line in f if line.startswith("STATE ")]
    # Greedy in-order match: each transition must be found after the previous one.
    pos, missing = 0, 0
    for state in want:
        try:
            pos = seen.index(state, pos) + 1
        except ValueError:
            missing += 1
    print(missing)


if __name__ == "__main__":
    if sys.argv[1:2] in (["-h"], ["--help"]):
        print(__doc__)
        sys.exit(0)
    if len(sys.argv) < 3 or any(a.startswith("-") for a in sys.argv[1:]):
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    check(sys.argv[1], sys.argv[2:])
