#!/usr/bin/env python3
"""Per-process resource samples from /proc (Linux, standard library only).

Each sample holds the process's cumulative CPU time (utime + stime), its
resident set, its open file descriptors and its threads. CPU percentages are
always computed from two cumulative readings, never from a single one, so a
figure over a window is exact whatever the sampling period.
"""
import argparse
import json
import os
import sys

CLOCK_TICKS = os.sysconf("SC_CLK_TCK")
PAGE_KB = os.sysconf("SC_PAGE_SIZE") // 1024


def read(pid):
    """One reading of `pid`, or None when the process is gone."""
    try:
        with open("/proc/%d/stat" % pid) as f:
            stat = f.read()
        fds = len(os.listdir("/proc/%d/fd" % pid))
    except (FileNotFoundError, ProcessLookupError):
        return None
    # The command name (field 2) may hold spaces and parentheses: split after
    # the last ')'. What follows starts at field 3 (state).
    fields = stat[stat.rindex(")") + 2:].split()
    if fields[0] in ("Z", "X"):  # exited, not yet reaped: nothing left to measure
        return None
    utime, stime = int(fields[11]), int(fields[12])  # fields 14, 15
    threads = int(fields[17])  # field 20
    rss_pages = int(fields[21])  # field 24
    return {
        "cpu_s": (utime + stime) / CLOCK_TICKS,
        "rss_kb": rss_pages * PAGE_KB,
        "fds": fds,
        "threads": threads,
    }


class Series:
    """The samples of one process, each stamped with seconds since `t0`."""

    def __init__(self, name, pid):
        self.name = name
        self.pid = pid
        self.samples = []
        self.gone = False

    def sample(self, t_s):
        reading = read(self.pid)
        if reading is None:
            self.gone = True
            return None
        reading["t_s"] = round(t_s, 3)
        if self.samples:
            prev = self.samples[-1]
            span = t_s - prev["t_s"]
            reading["cpu_pct"] = (round(100.0 * (reading["cpu_s"] - prev["cpu_s"]) / span, 3)
                                  if span > 0 else None)
        else:
            reading["cpu_pct"] = None
        self.samples.append(reading)
        return reading

    def cpu_pct_between(self, start_s, end_s):
        """CPU (% of one core) from the sample at or after `start_s` to the
        last sample at or before `end_s`; None without two such samples."""
        first = next((s for s in self.samples if s["t_s"] >= start_s - 0.5), None)
        last = next((s for s in reversed(self.samples) if s["t_s"] <= end_s + 0.5), None)
        if first is None or last is None or last["t_s"] <= first["t_s"]:
            return None
        return 100.0 * (last["cpu_s"] - first["cpu_s"]) / (last["t_s"] - first["t_s"])

    def summary(self, window_s):
        """CPU over the first and the last `window_s`; RSS, fds and threads at
        the start, after the first window, at the end and at most."""
        out = {"name": self.name, "pid": self.pid, "samples": self.samples}
        if not self.samples:
            return out
        t_first = self.samples[0]["t_s"]
        t_last = self.samples[-1]["t_s"]
        first = self.cpu_pct_between(t_first, t_first + window_s)
        last = self.cpu_pct_between(t_last - window_s, t_last)
        out["cpu_first_window_pct"] = rounded(first)
        out["cpu_last_window_pct"] = rounded(last)
        out["cpu_whole_run_pct"] = rounded(self.cpu_pct_between(t_first, t_last))
        out["cpu_ratio_last_to_first"] = (rounded(last / first)
                                          if first and last is not None else None)
        # At the start a process may still be loading: the value at the end
        # of the first window is the one to compare the last with.
        settled = next((s for s in reversed(self.samples)
                        if s["t_s"] <= t_first + window_s + 0.5), self.samples[0])
        for key in ("rss_kb", "fds", "threads"):
            values = [s[key] for s in self.samples]
            out[key + "_start"] = values[0]
            out[key + "_after_first_window"] = settled[key]
            out[key + "_last"] = values[-1]
            out[key + "_max"] = max(values)
        return out


def rounded(value, digits=3):
    return None if value is None else round(value, digits)


def main(argv):
    p = argparse.ArgumentParser(
        prog="procstat.py",
        description="One reading of each pid from /proc as JSON: cumulative CPU seconds, RSS, "
                    "open fds, threads (null for a process that is gone). The sampler of "
                    "endurance.py.")
    p.add_argument("pids", nargs="+", type=int, metavar="PID")
    args = p.parse_args(argv)
    print(json.dumps({str(pid): read(pid) for pid in args.pids}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
