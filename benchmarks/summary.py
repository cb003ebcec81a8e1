#!/usr/bin/env python3
"""Collects the JSON every benchmark of benchmarks/run.sh wrote into one
summary (bench-results/summary.json): the machine, the load, how long the run
took, and per area the figures a reader looks for first. With --check it
exits 1 when a figure the summary should hold is missing (the CI smoke test:
completeness, never the figures' values). Standard library only.

Usage: summary.py RESULTS_DIR [--seconds N] [--quick] [--load-start L] [--check]
"""
import argparse
import datetime
import json
import os
import platform
import subprocess
import sys


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def line_key(obj):
    name = obj.get("benchmark", "?")
    middleware = obj.get("middleware", "fastdds")
    inline = obj.get("inline_steps", False)
    dispatch = obj.get("observer_steps") == "dispatch"
    if middleware == "fastdds" and not inline and not dispatch:
        return name
    return "%s@%s%s%s" % (name, middleware, "+inline" if inline else "",
                          "+dispatch" if dispatch else "")


def load_json_lines(path):
    """bridge_http.json: one JSON object per line, keyed by "benchmark"; a
    benchmark run with other settings (middleware, inline steps) than its
    defaults gets "@<middleware>[+inline][+dispatch]" after its name."""
    found = {}
    try:
        with open(path) as f:
            for line in f:
                line = line.strip()
                if line.startswith("{"):
                    try:
                        obj = json.loads(line)
                    except ValueError:
                        continue
                    found[line_key(obj)] = obj
    except OSError:
        pass
    return found


def machine():
    model = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {"nproc": os.cpu_count(), "cpu_model": model, "kernel": platform.release(),
            "idle": idle_policy()}


def read_text(path):
    try:
        with open(path) as f:
            return f.read().strip()
    except OSError:
        return None


def idle_policy():
    """How an idle CPU waits: on a VM guest, a halted vCPU is woken through
    the hypervisor, which sets the floor of every cross-thread hand-off
    (docs/benchmarks.md, "The machine's idle halt"); the figures are only
    comparable with this beside them."""
    poll = read_text("/sys/module/haltpoll/parameters/guest_halt_poll_ns")
    return {
        "cpuidle_driver": read_text("/sys/devices/system/cpu/cpuidle/current_driver"),
        "guest_halt_poll_ns": int(poll) if poll is not None and poll.isdigit() else None,
    }


def wakeup_part(wakeup):
    """mtc-bench-wakeup's hand-offs, keyed "<placement>@<gap_us>us"."""
    if not wakeup:
        return None
    return {"%s@%dus" % (s.get("placement"), s.get("gap_us", 0)):
            {k: s.get(k) for k in ("wake_p50", "wake_p99", "notify_p50", "notify_p99")}
            for s in wakeup.get("series", [])}


def commit(root):
    try:
        return subprocess.run(["git", "-C", root, "rev-parse", "--short", "HEAD"],
                              capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def dds_part(dds):
    if not dds:
        return None
    series = {s["name"]: {k: s.get(k) for k in
                          ("p50", "p90", "p99", "p999", "max", "count", "timeouts",
                           "cpu_us_per_op", "legs_p50_us") if k in s}
              for s in dds.get("series", [])}
    cyclone = dds.get("cyclone") or {}
    return {"series": series,
            "cyclone": {k: cyclone.get(k) for k in
                        ("available", "why", "p50", "p90", "p99", "max", "cpu_us_per_op")},
            "cpus": dds.get("cpus"),
            "ratios": dds.get("ratios"), "targets": dds.get("targets"),
            "load_average_start": dds.get("load_average_start"),
            "load_average_end": dds.get("load_average_end")}


def bridge_part(lines):
    current = lines.get("bridge_http_current", {})
    stream = lines.get("bridge_http_dds_stream_latency", {})
    fanout = lines.get("bridge_http_fanout", {})
    return {
        "current": {k: current.get(k) for k in
                    ("requests_per_second", "latency_us", "server_cpu_us_per_request",
                     "meets_bar")} if current else None,
        "dds_to_stream": {k: stream.get(k) for k in
                          ("lost", "direct_parts", "from_transition_us", "legs_us",
                           "meets_bar")}
        if stream else None,
        # The same path with inline steps, and over Cyclone DDS (issue 9
        # section 5's target: p50 <= 100 us, p99 <= 1 ms).
        "dds_to_stream_variants": {
            key.split("@", 1)[1]: {k: line.get(k) for k in
                                   ("lost", "direct_parts", "from_transition_us", "legs_us")}
            for key, line in lines.items()
            if key.startswith("bridge_http_dds_stream_latency@")},
        "fanout": {k: fanout.get(k) for k in
                   ("clients", "lost", "all_clients_us", "last_client_us", "rss_kb",
                    "rss_growth_while_streaming_kb", "cpu_us_per_part", "meets_bar")}
        if fanout else None,
        "stream": lines.get("bridge_http_stream_latency"),
        "abuse": lines.get("bridge_abuse"),
    }


# What a complete summary holds: (path, test) pairs; a test gets the value.
def required(summary):
    dds = summary.get("dds_latency") or {}
    series = dds.get("series") or {}
    scale = summary.get("scale") or {}
    levels = {l.get("pairs"): l for l in scale.get("levels") or []}
    bridge = summary.get("bridge") or {}
    checks = []
    for name in ("udp_round_trip_2proc",
                 "raw_fastdds_listener_round_trip_udp_loopback_2proc",
                 "raw_fastdds_listener_round_trip_shm_udp_2proc",
                 "raw_fastdds_round_trip_shm_udp_2proc",
                 "mtc_transition_shm_udp_2proc", "mtc_handshake_shm_udp_2proc",
                 "mtc_transition_udp_loopback_2proc", "mtc_handshake_udp_loopback_2proc",
                 # run.sh measures every stepping mode, in the same rounds.
                 "mtc_transition_shm_udp_2proc_inline", "mtc_handshake_shm_udp_2proc_inline",
                 "mtc_handshake_shm_udp_2proc_executor"):
        s = series.get(name) or {}
        checks.append(("dds_latency.series.%s.count" % name, (s.get("count") or 0) > 0))
        checks.append(("dds_latency.series.%s.p999" % name, s.get("p999") is not None))
    for name in ("udp_round_trip_2proc", "mtc_handshake_shm_udp_2proc",
                 "raw_fastdds_listener_round_trip_shm_udp_2proc"):
        checks.append(("dds_latency.series.%s.cpu_us_per_op" % name,
                       (series.get(name) or {}).get("cpu_us_per_op") is not None))
    checks.append(("dds_latency.cyclone.p50",
                   (dds.get("cyclone") or {}).get("p50") is not None))
    checks.append(("dds_latency.ratios", bool(dds.get("ratios"))))
    for key in ("shm_udp", "shm_udp_executor", "shm_udp_inline"):
        checks.append(("dds_latency.targets." + key, key in (dds.get("targets") or {})))
    checks.append(("dds_latency.load_average_start", dds.get("load_average_start") is not None))
    one_cpu = (summary.get("dds_latency_one_cpu") or {}).get("series") or {}
    for name in ("raw_fastdds_listener_round_trip_shm_udp_2proc", "mtc_handshake_shm_udp_2proc",
                 "mtc_handshake_shm_udp_2proc_inline"):
        checks.append(("dds_latency_one_cpu.series.%s.count" % name,
                       ((one_cpu.get(name) or {}).get("count") or 0) > 0))
    wakeup = (summary.get("machine") or {}).get("wakeup") or {}
    checks.append(("machine.wakeup.same_cpu@200us", "same_cpu@200us" in wakeup))
    if (os.cpu_count() or 1) > 1:
        checks.append(("machine.wakeup.other_cpu@200us", "other_cpu@200us" in wakeup))
    for pairs in (1, 10, 100):
        level = levels.get(pairs) or {}
        checks.append(("scale.levels[pairs=%d].handshakes" % pairs,
                       (level.get("handshakes") or 0) > 0))
        checks.append(("scale.levels[pairs=%d].responder_rss_kb" % pairs,
                       (level.get("responder_rss_kb") or 0) > 0))
        checks.append(("scale.levels[pairs=%d].paced.handshakes" % pairs,
                       ((level.get("paced") or {}).get("handshakes") or 0) > 0))
        checks.append(("scale.levels[pairs=%d].paced.issue_delay" % pairs,
                       "p99" in ((level.get("paced") or {}).get("issue_delay") or {})))
    checks.append(("scale.startup.all_ready_ms",
                   ((scale.get("startup") or {}).get("all_ready_ms") or -1) > 0))
    # A build with Cyclone DDS measured its equipment series; then the scale
    # levels over Cyclone belong to the run too.
    if any("cyclone" in name for name in series):
        for part in ("scale_cyclone", "scale_cyclone_inline", "scale_cyclone_packed"):
            levels = {l.get("pairs"): l for l in (summary.get(part) or {}).get("levels") or []}
            for pairs in (1, 10, 100):
                checks.append(("%s.levels[pairs=%d].handshakes" % (part, pairs),
                               ((levels.get(pairs) or {}).get("handshakes") or 0) > 0))
    checks.append(("bridge.current.requests_per_second",
                   ((bridge.get("current") or {}).get("requests_per_second") or 0) > 0))
    checks.append(("bridge.dds_to_stream.from_transition_us",
                   (bridge.get("dds_to_stream") or {}).get("from_transition_us") is not None))
    for variant in ("fastdds+inline", "fastdds+dispatch"):
        checks.append(("bridge.dds_to_stream_variants." + variant,
                       ((bridge.get("dds_to_stream_variants") or {}).get(variant) or {})
                       .get("from_transition_us") is not None))
    fanout = bridge.get("fanout") or {}
    checks.append(("bridge.fanout.all_clients_us", fanout.get("all_clients_us") is not None))
    checks.append(("bridge.fanout.rss_kb", fanout.get("rss_kb") is not None))
    checks.append(("core", summary.get("core") is not None))
    return [path for path, ok in checks if not ok]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", help="the directory run.sh wrote the JSON files to")
    parser.add_argument("--seconds", type=float, help="how long the whole run took")
    parser.add_argument("--load-start", help="load average when the run started (1 5 15)")
    parser.add_argument("--quick", action="store_true", help="the run was a --quick one")
    parser.add_argument("--check", action="store_true",
                        help="exit 1 when a figure is missing")
    args = parser.parse_args()
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    r = args.results
    with open("/proc/loadavg") as f:
        load_end = [float(x) for x in f.read().split()[:3]]
    core = load_json(os.path.join(r, "core.json"))
    summary = {
        "generated_utc": datetime.datetime.now(datetime.timezone.utc).strftime(
            "%Y-%m-%dT%H:%M:%SZ"),
        "commit": commit(root),
        "machine": dict(machine(), wakeup=wakeup_part(load_json(os.path.join(r, "wakeup.json")))),
        "quick": args.quick,
        "run_seconds": args.seconds,
        "load_average_start": [float(x) for x in args.load_start.split()]
        if args.load_start else None,
        "load_average_end": load_end,
        "dds_latency": dds_part(load_json(os.path.join(r, "dds_latency.json"))),
        # The same benchmark with every process on one CPU (run.sh --cpus 0).
        "dds_latency_one_cpu": dds_part(load_json(os.path.join(r, "dds_latency_one_cpu.json"))),
        "scale": load_json(os.path.join(r, "scale.json")),
        "scale_cyclone": load_json(os.path.join(r, "scale_cyclone.json")),
        # The same levels with inline steps in both processes (run.sh).
        "scale_cyclone_inline": load_json(os.path.join(r, "scale_cyclone_inline.json")),
        # And with pack_callback_writes too.
        "scale_cyclone_packed": load_json(os.path.join(r, "scale_cyclone_packed.json")),
        "security": load_json(os.path.join(r, "security.json")),
        "bridge": bridge_part(load_json_lines(os.path.join(r, "bridge_http.json"))),
        "core": {"benchmarks": len(core.get("benchmarks", []))} if core else None,
    }
    missing = required(summary)
    summary["complete"] = not missing
    summary["missing"] = missing
    with open(os.path.join(r, "summary.json"), "w") as f:
        json.dump(summary, f, indent=1)
        f.write("\n")
    print(os.path.join(r, "summary.json"))
    if missing:
        print("summary.py: missing: " + ", ".join(missing), file=sys.stderr)
        if args.check:
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
