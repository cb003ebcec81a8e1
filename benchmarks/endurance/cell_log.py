#!/usr/bin/env python3
"""Reads mtc-cell's output as it is written and counts what the endurance
verdicts need. Each line of the cell is one write(2) to a pipe shared by the
supervisor and the three stations, so the order of the lines is the order in
which they were written:

  12:00:01.234  robot   | link mh1 -> cell-machine: LOST (deadline missed ...)

A LOST line read before the stop (the driver's SIGINT, or the supervisor's
"stopping every station") is a false alarm: nothing was frozen or killed.
After the stop the stations leave and their peers rightly report them lost.
"""
import argparse
import json
import re
import sys
import threading

LINE = re.compile(r"^\S+\s+(\w+)\s*\| (.*)$")
STARTED = re.compile(r"stations started: machine pid (\d+), robot pid (\d+), feeder pid (\d+)")
INJECTED = re.compile(r"!! .*: injected failure, scenario (\d+)")
# A requester's fault that arrived after the responder had finished: no effect.
INJECTED_LATE = re.compile(r"injected failure too late")
DONE = re.compile(r"^\s*(\w+)\s+done in ([0-9.]+) ms, both READY")
FAILED = re.compile(r"FAILED \(both sides FAIL\)|TIMED OUT after|could not raise the request")
LINK = re.compile(r"link (\S+) -> (\S+): (LOST|UP) \((.*)\)$")
SUMMARY = re.compile(r"cell summary: (\d+) cycles complete, (\d+) handshakes by the machine, "
                     r"(\d+) failures \((\d+) injected, (\d+) other\), (\d+) recovered")
UNRECOVERED = re.compile(r"could not recover|UNRECOVERED|exited unexpectedly|cannot start")
STOPPING = re.compile(r": stopping every station")
EXIT = re.compile(r"all stations stopped, exit code (-?\d+)")

KEEP = 20  # lines kept as examples of each kind of problem


class CellLog:
    def __init__(self, stream, log_file, clock, t0):
        self.stream = stream
        self.log_file = log_file
        self.clock = clock
        self.t0 = t0
        self.lock = threading.Lock()
        self.pids_known = threading.Event()
        self.station_pids = {}
        self.stopping = False
        self.handshakes = 0
        self.handshakes_by_service = {}
        self.handshakes_per_minute = {}
        self.slowest_handshake_ms = 0.0
        self.injected = 0
        self.injected_late = 0
        self.injected_by_scenario = {}
        self.requester_failures = 0
        self.false_alarms = []
        self.lost_after_stop = 0
        self.problems = []
        self.diagnostics = []
        self.summary = None
        self.exit_line_code = None
        self._thread = None

    def start(self):
        self._thread = threading.Thread(target=self._run, name="cell-log", daemon=True)
        self._thread.start()

    def join(self, timeout):
        if self._thread:
            self._thread.join(timeout)

    def mark_stopping(self):
        """Called just before the driver stops the cell."""
        with self.lock:
            self.stopping = True

    def _run(self):
        for raw in self.stream:
            line = raw.decode("utf-8", "replace").rstrip("\n")
            self.log_file.write(line + "\n")
            with self.lock:
                self.parse(line, self.clock() - self.t0)
        self.log_file.flush()

    def parse(self, line, t_s):
        m = LINE.match(line)
        if not m:
            return
        who, text = m.group(1), m.group(2)
        if STOPPING.search(text):
            self.stopping = True
        if (m2 := STARTED.search(text)):
            self.station_pids = {"machine": int(m2.group(1)), "robot": int(m2.group(2)),
                                 "feeder": int(m2.group(3))}
            self.pids_known.set()
        elif (m2 := INJECTED.search(text)):
            self.injected += 1
            key = m2.group(1)
            self.injected_by_scenario[key] = self.injected_by_scenario.get(key, 0) + 1
        elif INJECTED_LATE.search(text):
            self.injected_late += 1
        elif (m2 := DONE.match(text)):
            self.count_handshake(m2.group(1), float(m2.group(2)), t_s)
        elif FAILED.search(text):
            self.requester_failures += 1
        elif (m2 := LINK.search(text)):
            self.link_event(who, m2, line, t_s)
        elif (m2 := SUMMARY.search(text)):
            keys = ("cycles", "machine_handshakes", "failures", "injected", "other", "recovered")
            self.summary = {k: int(v) for k, v in zip(keys, m2.groups())}
            self.summary["stopped_on_unrecovered_failure"] = "UNRECOVERED" in text
        elif (m2 := EXIT.search(text)):
            self.exit_line_code = int(m2.group(1))
        elif text.startswith("runtime: ") and len(self.diagnostics) < KEEP:
            self.diagnostics.append(line)
        if UNRECOVERED.search(text) and len(self.problems) < KEEP:
            self.problems.append(line)

    def count_handshake(self, service, ms, t_s):
        self.handshakes += 1
        self.handshakes_by_service[service] = self.handshakes_by_service.get(service, 0) + 1
        minute = int(t_s // 60)
        self.handshakes_per_minute[minute] = self.handshakes_per_minute.get(minute, 0) + 1
        self.slowest_handshake_ms = max(self.slowest_handshake_ms, ms)

    def link_event(self, who, m, line, t_s):
        if m.group(3) != "LOST":
            return
        if self.stopping:
            self.lost_after_stop += 1
        else:
            self.false_alarms.append({"t_s": round(t_s, 3), "station": who, "line": line})

    def report(self):
        with self.lock:
            minutes = max(self.handshakes_per_minute, default=-1) + 1
            return {
                "handshakes_completed": self.handshakes,
                "handshakes_by_service": dict(sorted(self.handshakes_by_service.items())),
                "handshakes_per_minute": [self.handshakes_per_minute.get(m, 0)
                                          for m in range(minutes)],
                "slowest_handshake_ms": self.slowest_handshake_ms,
                "injected_failures": self.injected,
                "injected_too_late": self.injected_late,
                "injected_by_scenario": dict(sorted(self.injected_by_scenario.items())),
                "requester_failures_logged": self.requester_failures,
                "machine_summary": self.summary,
                "other_failures": None if self.summary is None else self.summary["other"],
                "false_alarms": len(self.false_alarms),
                "false_alarm_lines": self.false_alarms[:KEEP],
                "lost_after_stop": self.lost_after_stop,
                "unrecovered_or_dead": self.problems,
                "runtime_diagnostics": self.diagnostics,
                "exit_line_code": self.exit_line_code,
            }


def seconds_of_day(line):
    """The line's HH:MM:SS.mmm (UTC) in seconds, or None."""
    m = re.match(r"^(\d\d):(\d\d):(\d\d\.\d+)\s", line)
    return None if not m else int(m.group(1)) * 3600 + int(m.group(2)) * 60 + float(m.group(3))


def read_saved(path):
    """The report of a saved mtc-cell output, timed by its own timestamps."""
    log = CellLog(None, None, None, 0)
    first = None
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            t = seconds_of_day(line)
            if t is not None and first is None:
                first = t
            log.parse(line.rstrip("\n"), 0.0 if t is None else (t - first) % 86400)
    return log.report()


def main(argv):
    p = argparse.ArgumentParser(
        prog="cell_log.py",
        description="Counts of a saved mtc-cell output (e.g. bench-results/endurance-cell.log) "
                    "as JSON: handshakes, injected and other failures, LOST lines before and "
                    "after the stop. The log reader of endurance.py.")
    p.add_argument("log", metavar="CELL_LOG")
    args = p.parse_args(argv)
    try:
        report = read_saved(args.log)
    except OSError as e:
        sys.stderr.write("cell_log.py: %s\n" % e)
        return 1
    print(json.dumps(report, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
