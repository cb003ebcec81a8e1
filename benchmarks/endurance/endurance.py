#!/usr/bin/env python3
"""Endurance run of the simulated cell with the bridge, at their defaults.

Starts mtc-bridge and mtc-cell (supervisor + machine, robot, feeder
processes) on one DDS domain, samples every process every --interval
seconds (CPU, RSS, open file descriptors, threads), keeps a streaming HTTP
client on the bridge that checks its sequence numbers, reads the cell's
output, then stops the cell (SIGINT) and the bridge, and writes a JSON
summary and a PNG plot. Exit code 0 when every verdict passes, 1 when one
fails, 2 on a usage error.

Verdicts: each station's and the bridge's CPU in the last --window seconds
is at most --cpu-ratio times its CPU in the first, times the drift of a
reference load (reference_load.py: fixed work, sampled alike) when the
machine slowed during the run; no LOST line before the
stop (false comms-loss alarm); no machine step failed other than by an
injected fault, none unrecovered; the stream's sequences strictly increase
with no gap; every process lives until the stop and exits 0.

Must run inside the loopback-only namespace (scripts/netns-run.sh), like
everything that starts DDS; benchmarks/endurance/run.sh does that.
"""
import argparse
import ctypes
import json
import os
import signal
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import cell_log  # noqa: E402
import plot  # noqa: E402
import procstat  # noqa: E402
import stream_check  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(HERE))
WATCHED = ("machine", "robot", "feeder", "bridge")  # the CPU verdict's processes
REFERENCE = "reference"  # reference_load.py: the machine's own drift


# After "--transport loopback", which the callers write out (the transport
# guard, tests/scripts/check_transport_chosen.py, reads the argument lists).
def cell_args(args):
    extra = [a for spec in args.middleware for a in ("--middleware", spec)]
    return ["--domain", str(args.domain)] + extra


def bridge_args(args):
    return ["--domain-ids", str(args.domain), "--port", str(args.port),
            "--middleware", args.bridge_middleware]


def parse_args(argv):
    p = argparse.ArgumentParser(
        prog="endurance.py", description=__doc__.split("\n\n")[0],
        epilog="Inside the namespace: scripts/netns-run.sh benchmarks/endurance/endurance.py ...")
    build = os.environ.get("MTC_BUILD_DIR", os.path.join(ROOT, "build"))
    p.add_argument("--build", default=build, help="build dir (default $MTC_BUILD_DIR or build/)")
    p.add_argument("--minutes", type=float, default=30.0, help="run length (default 30)")
    p.add_argument("--interval", type=float, default=10.0, help="sampling period, s (default 10)")
    p.add_argument("--window", type=float, default=60.0,
                   help="length of the first and last CPU windows, s (default 60)")
    p.add_argument("--cpu-ratio", type=float, default=1.5,
                   help="largest allowed last/first window CPU ratio (default 1.5)")
    p.add_argument("--domain", type=int, default=115, help="DDS domain id (default 115)")
    p.add_argument("--port", type=int, default=5115, help="bridge HTTP port (default 5115)")
    p.add_argument("--out", default=os.path.join(ROOT, "bench-results"),
                   help="directory of the results (default bench-results/)")
    p.add_argument("--name", default="endurance",
                   help="file stem: NAME.json, NAME.png, NAME-cell.log, NAME-bridge.log")
    p.add_argument("--no-plot", action="store_true", help="skip the PNG")
    p.add_argument("--middleware", action="append", default=[], metavar="SPEC",
                   help="handed to mtc-cell as --middleware SPEC (repeatable), e.g. "
                        "robot=cyclone: a cell on two DDS implementations")
    p.add_argument("--bridge-middleware", default="fastdds", choices=("fastdds", "cyclone"),
                   help="the bridge's DDS implementation (default fastdds)")
    a = p.parse_args(argv)
    if a.interval <= 0 or a.window < a.interval or a.cpu_ratio <= 1.0:
        p.error("need --interval > 0, --window >= --interval and --cpu-ratio > 1")
    if a.minutes * 60 < 2 * a.window:
        p.error("the run must last at least two windows (%.0f s)" % (2 * a.window))
    if not 0 <= a.domain <= 232 or not 1 <= a.port <= 65535:
        p.error("--domain must be 0-232 and --port 1-65535")
    return a


def die_with_parent():
    """In the child before exec: SIGTERM when the driver dies (killed by a
    ctest timeout, say), so no cell or bridge outlives its run."""
    PR_SET_PDEATHSIG = 1
    ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGTERM)


class Run:
    """The processes of one run and everything measured about them."""

    def __init__(self, args):
        self.args = args
        self.clock = time.monotonic
        self.t0 = self.clock()
        os.makedirs(args.out, exist_ok=True)
        self.stem = os.path.join(args.out, args.name)
        self.cell = None
        self.bridge = None
        self.reference = None
        self.series = []
        self.events = []  # what went wrong while running, in words
        self.log = None
        self.stream = stream_check.StreamCheck(args.port, clock=self.clock, t0=self.t0)

    def t(self):
        return self.clock() - self.t0

    def start(self):
        apps = os.path.join(self.args.build, "apps")
        bridge_log = open(self.stem + "-bridge.log", "w")
        self.bridge = subprocess.Popen(
            [os.path.join(apps, "mtc-bridge"), "--transport", "loopback"] + bridge_args(self.args),
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=die_with_parent)
        # The bridge says when it listens: start the stream then, not after a sleep.
        first = self.bridge.stdout.readline().decode("utf-8", "replace")
        bridge_log.write(first)
        if "serving MTConnect" not in first:
            raise RuntimeError("mtc-bridge did not start: " + first.strip())
        self._drain(self.bridge.stdout, bridge_log)
        self.reference = subprocess.Popen(
            [sys.executable, os.path.join(HERE, "reference_load.py")], preexec_fn=die_with_parent)
        self.stream.start()
        self.cell = subprocess.Popen(
            [os.path.join(apps, "mtc-cell"), "--transport", "loopback"] + cell_args(self.args),
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, preexec_fn=die_with_parent)
        self.log = cell_log.CellLog(self.cell.stdout, open(self.stem + "-cell.log", "w"),
                                    self.clock, self.t0)
        self.log.start()
        if not self.log.pids_known.wait(30):
            raise RuntimeError("mtc-cell did not report its stations' pids within 30 s")
        self.series = [procstat.Series("supervisor", self.cell.pid)]
        self.series += [procstat.Series(n, p) for n, p in self.log.station_pids.items()]
        self.series.append(procstat.Series("bridge", self.bridge.pid))
        self.series.append(procstat.Series(REFERENCE, self.reference.pid))

    @staticmethod
    def _drain(pipe, out):
        def copy():
            for raw in pipe:
                out.write(raw.decode("utf-8", "replace"))
            out.close()
        threading.Thread(target=copy, daemon=True).start()

    def sample_until(self, end_s):
        """Samples every interval until `end_s` or until a process dies."""
        next_at = 0.0
        while True:
            now = self.t()
            if now >= next_at or self.cell.poll() is not None:
                for s in self.series:
                    s.sample(self.t())
                dead = [s.name for s in self.series if s.gone]
                if dead:
                    self.events.append("%s gone at %.0f s" % (", ".join(dead), self.t()))
                    return False
                self._progress()
                if now >= end_s:
                    return True
                next_at = min(next_at + self.args.interval, end_s)
            # Waiting on the cell: its death wakes the loop for a last sample.
            try:
                self.cell.wait(max(0.0, next_at - self.t()))
            except subprocess.TimeoutExpired:
                pass

    def _progress(self):
        line = "  %6.0f s " % self.t()
        for s in self.series:
            cpu = s.samples[-1].get("cpu_pct") if s.samples else None
            line += " %s %s%%" % (s.name, "-" if cpu is None else "%.1f" % cpu)
        print(line, flush=True)

    def stop(self):
        if self.log:
            self.log.mark_stopping()
        codes = {}
        for name, proc in (("cell", self.cell), ("bridge", self.bridge),
                           (REFERENCE, self.reference)):
            if proc is None:
                continue
            if proc.poll() is None:
                proc.send_signal(signal.SIGINT)
            try:
                codes[name] = proc.wait(30)
            except subprocess.TimeoutExpired:
                self.events.append("%s did not stop within 30 s of SIGINT: killed" % name)
                proc.kill()
                codes[name] = proc.wait()
        if self.log:
            self.log.join(10)
        self.stream.join(15)
        return codes


def machine_drift(processes):
    """How much more the reference load's fixed work cost in the last window
    than in the first: 1.0 when it cost the same or less (a faster machine
    never tightens the verdict), None without its figures."""
    ref = next((p for p in processes if p["name"] == REFERENCE), None)
    if ref is None or not ref.get("cpu_first_window_pct") or ref.get("cpu_last_window_pct") is None:
        return None
    return max(1.0, ref["cpu_last_window_pct"] / ref["cpu_first_window_pct"])


def cpu_flat(cpu_ratio, processes):
    """Each watched process's last window within cpu_ratio times its first,
    times the machine's drift: a leak grows one process against the fixed
    reference, a slow host grows them all with it."""
    drift = machine_drift(processes)
    allowed = cpu_ratio * (drift or 1.0)
    flat, detail = drift is not None, []
    for p in processes:
        if p["name"] not in WATCHED:
            continue
        first, last = p.get("cpu_first_window_pct"), p.get("cpu_last_window_pct")
        ok = first is not None and last is not None and last <= allowed * first
        flat = flat and ok
        detail.append("%s %s -> %s %%" % (p["name"], first, last))
    return {"pass": flat, "machine_drift": None if drift is None else round(drift, 3),
            "detail": "last <= %.2f x first window (%.2f x machine drift %s): %s"
                      % (allowed, cpu_ratio, "unknown" if drift is None else "%.2f" % drift,
                         "; ".join(detail))}


def verdicts(args, processes, cell, stream, codes, events):
    out = {"cpu_flat": cpu_flat(args.cpu_ratio, processes)}
    out["no_false_alarms"] = {"pass": cell["false_alarms"] == 0,
                              "detail": "%d LOST lines before the stop" % cell["false_alarms"]}
    summary = cell["machine_summary"]
    failures_ok = (summary is not None and summary["other"] == 0
                   and not summary["stopped_on_unrecovered_failure"]
                   and summary["failures"] == summary["recovered"]
                   and not cell["unrecovered_or_dead"])
    out["no_other_failures"] = {
        "pass": failures_ok,
        "detail": ("no cell summary" if summary is None else
                   "%d failures: %d injected, %d other; %d recovered; %d unrecovered/dead lines"
                   % (summary["failures"], summary["injected"], summary["other"],
                      summary["recovered"], len(cell["unrecovered_or_dead"])))}
    out["handshakes_progress"] = {"pass": cell["handshakes_completed"] > 0,
                                  "detail": "%d handshakes" % cell["handshakes_completed"]}
    out["stream_sequences"] = {
        "pass": stream.ok(),
        "detail": "%d parts, %d observations, %d gaps, %d regressions, %d errors"
                  % (stream.parts, stream.observations, stream.gap_count,
                     stream.regression_count, len(stream.errors))}
    alive = not events and codes.get("cell") == 0 and codes.get("bridge") == 0
    out["processes_lived"] = {"pass": alive, "detail": "exit codes %s; %s"
                              % (codes, "; ".join(events) or "all alive until the stop")}
    return out


def load_average():
    with open("/proc/loadavg") as f:
        return [float(x) for x in f.read().split()[:3]]


def report(args, run, codes, load_start):
    processes = [s.summary(args.window) for s in run.series]
    cell = run.log.report() if run.log else cell_log.CellLog(None, None, None, 0).report()
    result = {
        "benchmark": "endurance",
        "title": "mtc-cell + mtc-bridge at defaults, %.0f min, sampled every %.0f s"
                 % (args.minutes, args.interval),
        "started_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime(time.time() - run.t())),
        "duration_s": round(max((s.samples[-1]["t_s"] for s in run.series if s.samples),
                                default=0), 1),
        "interval_s": args.interval, "window_s": args.window, "cpu_ratio_limit": args.cpu_ratio,
        "cores": os.cpu_count(), "load_average_start": load_start,
        "load_average_end": load_average(),
        "config": {"domain": args.domain, "port": args.port, "build": args.build,
                   "cell": "mtc-cell --transport loopback %s (defaults: 100 ms x 3 heartbeat)"
                           % " ".join(cell_args(args)),
                   "bridge": "mtc-bridge --transport loopback " + " ".join(bridge_args(args))},
        "processes": processes, "cell": cell, "stream": run.stream.summary(),
        "exit_codes": codes, "events": run.events,
    }
    result["verdicts"] = verdicts(args, processes, cell, run.stream, codes, run.events)
    result["pass"] = all(v["pass"] for v in result["verdicts"].values())
    return result


def print_figures(result):
    w = result["window_s"]
    print("\nprocess     CPU %%: first %.0fs  last %.0fs  ratio | RSS MiB: after %.0fs  last   max | "
          "fds: after %.0fs last | threads: after %.0fs last" % (w, w, w, w, w))
    for p in result["processes"]:
        if "rss_kb_last" not in p:
            print("%-10s  no samples" % p["name"])
            continue
        print("%-10s  %14s %9s %6s | %15.1f %6.1f %5.1f | %12d %4d | %16d %4d"
              % (p["name"], p["cpu_first_window_pct"], p["cpu_last_window_pct"],
                 p["cpu_ratio_last_to_first"], p["rss_kb_after_first_window"] / 1024,
                 p["rss_kb_last"] / 1024, p["rss_kb_max"] / 1024, p["fds_after_first_window"],
                 p["fds_last"], p["threads_after_first_window"], p["threads_last"]))
    c, s = result["cell"], result["stream"]
    print("handshakes completed %d (per minute %s), injected failures %d, other failures %s, "
          "false alarms %d (LOST after the stop: %d)"
          % (c["handshakes_completed"], c["handshakes_per_minute"], c["injected_failures"],
             c["other_failures"], c["false_alarms"], c["lost_after_stop"]))
    print("stream: %d parts, %d observations (per minute %s), sequences %s..%s, %d gaps, "
          "%d regressions, errors %s"
          % (s["parts"], s["observations"], s["observations_per_minute"], s["first_sequence"],
             s["next_sequence"], s["gaps"], s["regressions"], s["errors"] or "none"))
    for line in c["false_alarm_lines"][:5] + c["unrecovered_or_dead"][:5]:
        print("  " + line["line"] if isinstance(line, dict) else "  " + line)
    for name, v in result["verdicts"].items():
        print("%-20s %s  %s" % (name, "PASS" if v["pass"] else "FAIL", v["detail"]))
    print("endurance: %s" % ("PASS" if result["pass"] else "FAIL"))


def main(argv):
    args = parse_args(argv)
    if os.environ.get("MTC_IN_NETNS") != "1":
        sys.stderr.write("endurance.py: run it inside the loopback-only namespace: "
                         "scripts/netns-run.sh %s ...\n" % sys.argv[0])
        return 2
    for exe in ("mtc-cell", "mtc-bridge"):
        if not os.access(os.path.join(args.build, "apps", exe), os.X_OK):
            sys.stderr.write("endurance.py: %s not built in %s/apps\n" % (exe, args.build))
            return 2
    load_start = load_average()
    run = Run(args)
    codes = {}
    try:
        run.start()
        print("endurance: %.1f min, domain %d, port %d, pids %s"
              % (args.minutes, args.domain, args.port,
                 {s.name: s.pid for s in run.series}), flush=True)
        run.sample_until(args.minutes * 60)
    except RuntimeError as e:
        run.events.append(str(e))
    except KeyboardInterrupt:
        run.events.append("interrupted at %.0f s" % run.t())
    finally:
        codes = run.stop()
    result = report(args, run, codes, load_start)
    with open(run.stem + ".json", "w") as f:
        json.dump(result, f, indent=1)
    print_figures(result)
    if not args.no_plot:
        problem = plot.plot(result, run.stem + ".png")
        print("plot: %s" % (problem or run.stem + ".png"))
    print("summary: %s.json" % run.stem)
    return 0 if result["pass"] else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
