#!/usr/bin/env python3
"""A streaming MTConnect client that checks the bridge's sequence numbers.

It holds one `/sample?interval=...` request open for the whole run (an
HTTP/1.1 chunked `multipart/x-mixed-replace` stream, as a real dashboard
would), starting at the buffer's first sequence. Every part is a
MTConnectStreams document; without a path filter it carries every
observation of its range, so the checks are exact:

  * the sequences of a part, sorted, are consecutive and free of duplicates;
  * the first sequence of a part is the previous part's nextSequence (no
    observation skipped or repeated between parts);
  * the last sequence of a part is its own nextSequence - 1;
  * nextSequence never goes back.

One stream rather than repeated polls with `from=`: the stream is the
bridge's harder path (its own timer, a plan carried from part to part, a
writer that must keep up) and a poller's checks would be the same.
"""
import argparse
import http.client
import json
import sys
import threading
import time
import xml.etree.ElementTree as ET


def local(tag):
    return tag.rsplit("}", 1)[-1]


class StreamCheck:
    def __init__(self, port, interval_ms=500, count=1000, clock=time.monotonic, t0=None):
        self.port = port
        self.path = "/sample?interval=%d&count=%d" % (interval_ms, count)
        self.clock = clock
        self.t0 = clock() if t0 is None else t0
        self.parts = 0
        self.empty_parts = 0
        self.observations = 0
        self.unavailable = 0
        self.first_sequence = None
        self.next_sequence = None
        self.gaps = []  # (expected, got) pairs, the first few
        self.gap_count = 0
        self.regression_count = 0
        self.errors = []
        self.per_minute = {}  # minute index -> observations received
        self.unavailable_per_minute = {}
        self.ended_cleanly = False
        self._thread = None

    # -- running -----------------------------------------------------------

    def start(self):
        self._thread = threading.Thread(target=self._run, name="stream", daemon=True)
        self._thread.start()

    def join(self, timeout):
        if self._thread:
            self._thread.join(timeout)
            if self._thread.is_alive():
                self.errors.append("the stream did not end within %.0f s of the stop" % timeout)

    def _run(self):
        try:
            conn = http.client.HTTPConnection("127.0.0.1", self.port, timeout=60)
            conn.request("GET", self.path)
            resp = conn.getresponse()
            ctype = resp.getheader("Content-Type", "")
            if resp.status != 200 or "boundary=" not in ctype:
                self.errors.append("stream refused: HTTP %d %s" % (resp.status, ctype))
                return
            self._read_parts(resp, ctype.split("boundary=", 1)[1].strip())
        except (OSError, http.client.HTTPException) as e:
            self.errors.append("stream broken: %r" % (e,))

    def _read_parts(self, resp, boundary):
        start = ("--" + boundary).encode()
        end = start + b"--"
        while True:
            line = resp.readline()
            if not line:
                self.errors.append("stream closed without its final boundary")
                return
            line = line.strip()
            if line == end:
                self.ended_cleanly = True
                return
            if line != start:
                continue
            length = None
            while True:
                header = resp.readline().strip()
                if not header:
                    break
                name, _, value = header.decode("latin-1").partition(":")
                if name.strip().lower() == "content-length":
                    length = int(value.strip())
            if length is None:
                self.errors.append("part without Content-length")
                return
            self.check_part(resp.read(length))

    # -- checking ----------------------------------------------------------

    def check_part(self, body):
        try:
            root = ET.fromstring(body)
        except ET.ParseError as e:
            self.errors.append("part is not XML: %s" % e)
            return
        if local(root.tag) == "MTConnectError":
            codes = [e.get("errorCode", "") + ": " + (e.text or "").strip()
                     for e in root.iter() if local(e.tag) == "Error"]
            self.errors.append("error part: %s" % "; ".join(codes))
            return
        header = next((e for e in root.iter() if local(e.tag) == "Header"), None)
        if header is None or header.get("nextSequence") is None:
            self.errors.append("part without a Header nextSequence")
            return
        next_seq = int(header.get("nextSequence"))
        seqs = []
        unavailable = 0
        for e in root.iter():
            s = e.get("sequence")
            if s is not None:
                seqs.append(int(s))
                unavailable += (e.text or "").strip() == "UNAVAILABLE"
        seqs.sort()
        self.parts += 1
        minute = int((self.clock() - self.t0) // 60)
        self.per_minute[minute] = self.per_minute.get(minute, 0) + len(seqs)
        # Items read UNAVAILABLE when the bridge loses a device: expected at
        # the start and the stop, a false alarm of the bridge in between.
        self.unavailable += unavailable
        if unavailable:
            self.unavailable_per_minute[minute] = (self.unavailable_per_minute.get(minute, 0)
                                                   + unavailable)
        self._check_sequences(seqs, next_seq)

    def _check_sequences(self, seqs, next_seq):
        expected = self.next_sequence
        if expected is None:  # first part: starts wherever the buffer starts
            expected = seqs[0] if seqs else next_seq
            self.first_sequence = expected
        if next_seq < expected:
            self._regression(expected, next_seq)
        if not seqs:
            self.empty_parts += 1
            if next_seq > expected:
                self._gap(expected, next_seq)
        for s in seqs:
            if s > expected:
                self._gap(expected, s)
            elif s < expected:
                self._regression(expected, s)
            expected = s + 1
        if seqs and next_seq != seqs[-1] + 1:
            if next_seq > seqs[-1] + 1:
                self._gap(seqs[-1] + 1, next_seq)
            else:
                self._regression(seqs[-1] + 1, next_seq)
        self.observations += len(seqs)
        self.next_sequence = max(next_seq, self.next_sequence or 0)

    def _gap(self, expected, got):
        self.gap_count += 1
        if len(self.gaps) < 10:
            self.gaps.append({"expected": expected, "got": got, "kind": "gap"})

    def _regression(self, expected, got):
        self.regression_count += 1
        if len(self.gaps) < 10:
            self.gaps.append({"expected": expected, "got": got, "kind": "regression"})

    # -- report ------------------------------------------------------------

    def summary(self):
        return {
            "request": self.path,
            "parts": self.parts,
            "empty_parts": self.empty_parts,
            "observations": self.observations,
            "first_sequence": self.first_sequence,
            "next_sequence": self.next_sequence,
            "gaps": self.gap_count,
            "regressions": self.regression_count,
            "first_problems": self.gaps,
            "unavailable_values": self.unavailable,
            "unavailable_values_per_minute": {str(m): n for m, n in
                                              sorted(self.unavailable_per_minute.items())},
            "observations_per_minute": [self.per_minute.get(m, 0)
                                        for m in range(max(self.per_minute, default=-1) + 1)],
            "ended_with_final_boundary": self.ended_cleanly,
            "errors": self.errors,
        }

    def ok(self):
        return (self.parts > 0 and self.observations > 0 and self.gap_count == 0
                and self.regression_count == 0 and not self.errors)


def main(argv):
    p = argparse.ArgumentParser(
        prog="stream_check.py",
        description="Holds a /sample stream on a running mtc-bridge for --seconds and prints the "
                    "sequence check as JSON; exit 1 on a gap, a regression or an error. The "
                    "stream client of endurance.py. Run it where the bridge is reachable (inside "
                    "its namespace).")
    p.add_argument("--port", type=int, required=True, help="the bridge's HTTP port")
    p.add_argument("--seconds", type=float, default=10.0, help="how long (default 10)")
    p.add_argument("--interval-ms", type=int, default=500, help="stream interval (default 500)")
    args = p.parse_args(argv)
    if not 1 <= args.port <= 65535 or args.seconds <= 0 or args.interval_ms < 0:
        p.error("need --port 1-65535, --seconds > 0, --interval-ms >= 0")
    check = StreamCheck(args.port, interval_ms=args.interval_ms)
    check.start()
    time.sleep(args.seconds)  # checking for that long is the point; the thread is a daemon
    print(json.dumps(check.summary(), indent=1))
    return 0 if check.ok() else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
