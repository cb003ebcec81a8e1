#!/usr/bin/env python3
"""A running demo cell (mtc-cell) and bridge (mtc-bridge) for the tests of
the live page and the JSON documents. Run inside the loopback-only
namespace (scripts/netns-run.sh): both speak DDS. The processes die with
the test (PR_SET_PDEATHSIG), so a ctest timeout leaves nothing behind."""
import ctypes
import json
import os
import signal
import subprocess
import threading
import time
import urllib.error
import urllib.request


def _die_with_parent():
    PR_SET_PDEATHSIG = 1
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGTERM)


def _drain(pipe, sink):
    def copy():
        for raw in pipe:
            sink.append(raw.decode("utf-8", "replace"))
    threading.Thread(target=copy, daemon=True).start()


class LiveCell:
    """The bridge, and the cell unless `defer_cell` (then start_cell()).
    `timing` is (heartbeat ms, missed heartbeats) of both: a headless
    browser starting beside them on two shared cores can starve a process
    for longer than the default 300 ms lease, and every handshake in flight
    would then end in a (correct) comms-loss FAIL."""

    def __init__(self, build, domain, port, cell_args=(), timing=(100, 3), defer_cell=False):
        self.apps = os.path.join(build, "apps")
        self.domain = domain
        self.port = port
        self.cell_args = list(cell_args)
        self.timing = ["--heartbeat-ms", str(timing[0]), "--missed-heartbeats", str(timing[1])]
        self.defer_cell = defer_cell
        self.bridge = None
        self.cell = None
        self.bridge_log = []
        self.cell_log = []

    def __enter__(self):
        self.bridge = subprocess.Popen(
            [os.path.join(self.apps, "mtc-bridge"), "--transport", "loopback",
             "--domain-ids", str(self.domain),
             "--port", str(self.port)] + self.timing,
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=_die_with_parent)
        first = self.bridge.stdout.readline().decode("utf-8", "replace")
        self.bridge_log.append(first)
        if "serving MTConnect" not in first:
            raise RuntimeError("mtc-bridge did not start: " + first.strip())
        _drain(self.bridge.stdout, self.bridge_log)
        if not self.defer_cell:
            self.start_cell()
        return self

    def start_cell(self):
        self.cell = subprocess.Popen(
            [os.path.join(self.apps, "mtc-cell"), "--transport", "loopback",
             "--domain", str(self.domain)] + self.timing +
            self.cell_args,
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=_die_with_parent)
        _drain(self.cell.stdout, self.cell_log)

    def __exit__(self, *exc):
        for proc in (self.cell, self.bridge):
            if proc and proc.poll() is None:
                proc.send_signal(signal.SIGINT)
        for proc in (self.cell, self.bridge):
            if proc:
                try:
                    proc.wait(30)
                except subprocess.TimeoutExpired:
                    proc.kill()
                    proc.wait()
        return False

    @property
    def url(self):
        return "http://127.0.0.1:%d" % self.port

    def get(self, path, accept=None):
        """(status, content type, body bytes) of GET path."""
        request = urllib.request.Request(self.url + path)
        if accept:
            request.add_header("Accept", accept)
        try:
            with urllib.request.urlopen(request, timeout=10) as r:
                return r.status, r.headers.get("Content-Type"), r.read()
        except urllib.error.HTTPError as e:
            return e.code, e.headers.get("Content-Type"), e.read()

    def json(self, path):
        status, _, body = self.get(path + ("&" if "?" in path else "?") + "format=json")
        return status, json.loads(body)

    def wait_for(self, what, condition, timeout_s=60.0, poll_s=0.05):
        """Polls `condition` until it returns a true value; raises naming
        `what` after timeout_s (or when a process died)."""
        end = time.monotonic() + timeout_s
        while time.monotonic() < end:
            for name, proc in (("bridge", self.bridge), ("cell", self.cell)):
                if proc is not None and proc.poll() is not None:
                    raise RuntimeError("%s exited (%s) while waiting for %s:\n%s" % (
                        name, proc.returncode, what,
                        "".join((self.bridge_log if name == "bridge" else self.cell_log)[-20:])))
            value = condition()
            if value:
                return value
            time.sleep(poll_s)
        raise TimeoutError("no %s within %.0f s" % (what, timeout_s))

    def completed_since(self, from_sequence):
        """(sequence, dataItemId) of the responses COMPLETE the bridge holds
        from `from_sequence` on (one page of at most 1000 observations),
        oldest first."""
        status, doc = self.json("/sample?from=%d&count=1000" % from_sequence)
        if status != 200:
            return []
        out = []
        streams = doc["MTConnectStreams"]["Streams"]
        for device in streams.get("DeviceStream", []):
            for component in device["ComponentStream"]:
                for observations in component.get("Events", {}).values():
                    for o in observations:
                        if o.get("subType") == "RESPONSE" and o.get("value") == "COMPLETE":
                            out.append((o["sequence"], o["dataItemId"]))
        return sorted(out)


if __name__ == "__main__":
    import argparse
    import sys
    argparse.ArgumentParser(
        description=__doc__ + "\nA module for check_json_documents.py and check_browser_page.py: "
        "it runs nothing on its own.").parse_args()
    sys.stderr.write("live_cell.py: a module, not a program (see --help)\n")
    sys.exit(2)
