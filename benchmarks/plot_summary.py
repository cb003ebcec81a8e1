#!/usr/bin/env python3
"""Draws the plots of benchmarks/run.sh with gnuplot: the latency CDFs per
transport (from mtc-bench-dds-latency --samples-out), the scaling curve
(from mtc-bench-scale) and the same latencies spread over the machine's
CPUs and on one CPU (placement.png, from both dds_latency passes). Standard
library only; prints the files it wrote and skips (with a note) what it has
no data or no gnuplot for.

Usage: plot_summary.py RESULTS_DIR
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

LABELS = {
    "udp_round_trip_2proc": "raw UDP RTT",
    "raw_fastdds_listener_round_trip": "Fast DDS RTT, listener echo",
    "raw_fastdds_round_trip": "Fast DDS RTT, WaitSet",
    "mtc_transition": "mtc transition (one way)",
    "mtc_handshake": "mtc handshake",
}


MODES = {"_inline": ", inline steps", "_executor": ", steps on the executor"}


def label(name):
    mode = ""
    for suffix, text in MODES.items():
        if name.endswith(suffix):
            name, mode = name[:-len(suffix)], text
    for prefix, text in LABELS.items():
        if name.startswith(prefix):
            procs = "1 proc" if name.endswith("_1proc") else "2 proc"
            return "%s, %s%s" % (text, procs, mode)
    return name


def terminal():
    out = subprocess.run(["gnuplot", "-e", "set terminal"], capture_output=True, text=True)
    if "pngcairo" in out.stdout + out.stderr:
        return 'set terminal pngcairo size 1100,650 font "sans,11"\n'
    return "set terminal png size 1100,650\n"


def draw(stem, title, body):
    """Writes STEM.gp (terminal, output STEM.png, title, then `body`), runs
    gnuplot on it and returns the PNG's path."""
    with open(stem + ".gp", "w") as f:
        f.write(terminal() + 'set output "%s.png"\nset title "%s"\n' % (stem, title) + body)
    subprocess.run(["gnuplot", stem + ".gp"], check=True)
    return stem + ".png"


def plot_cdfs(results, samples, cyclone):
    written = []
    for transport, title in (("shm_udp", "SHM+UDP"), ("udp_loopback", "UDP loopback")):
        names = [n for n in samples if samples[n] and
                 (transport in n or (transport == "udp_loopback" and n.startswith("udp_")))]
        if not names:
            continue
        plots = []
        for n in names:
            dat = os.path.join(results, "cdf_%s.dat" % n)
            values = samples[n]
            with open(dat, "w") as f:
                for i, v in enumerate(values):
                    f.write("%s %.5f\n" % (v, (i + 1) / len(values)))
            plots.append('"%s" using 1:2 with lines lw 2 title "%s"' % (dat, label(n)))
        if transport == "udp_loopback" and cyclone and cyclone.get("available"):
            dat = os.path.join(results, "cdf_cyclone.dat")
            with open(dat, "w") as f:
                for key, frac in (("p50", 0.5), ("p90", 0.9), ("p99", 0.99)):
                    f.write("%s %s\n" % (cyclone[key], frac))
            plots.append('"%s" using 1:2 with linespoints pt 7 title '
                         '"Cyclone RTT (ddsperf p50/p90/p99)"' % dat)
        stem = os.path.join(results, "latency_cdf_%s" % transport)
        written.append(draw(stem, "Latency CDF, %s, one run (x log scale)" % title,
                            'set xlabel "microseconds"\nset ylabel "fraction of samples"\n'
                            "set logscale x\nset grid\nset key bottom right\n"
                            "set yrange [0:1]\nplot " + ", ".join(plots) + "\n"))
    return written


def write_scale_dat(path, levels):
    with open(path, "w") as f:
        f.write("# pairs handshakes_per_s p50_ms p99_ms paced_p99_ms\n")
        for l in levels:
            p = l.get("paced")
            f.write("%s %s %s %s %s\n" % (l["pairs"], l["handshakes_per_s"], l["p50"] / 1000,
                                         l["p99"] / 1000, p["p99"] / 1000 if p else "NaN"))


def plot_scale(results, scale, cyclone=None, cyclone_modes=None):
    """cyclone_modes: {"inline": ..., "packed": ...}, scale_cyclone_<mode>.json."""
    levels = scale.get("levels") or []
    if not levels:
        return []
    dat = os.path.join(results, "scale.dat")
    write_scale_dat(dat, levels)
    rate = next((l["paced"]["offered_per_s"] for l in levels if l.get("paced")), None)
    extra = (', "%s" using 1:5 axes x1y2 with linespoints lw 2 dt 3 '
             'title "p99 paced at %g/s (ms)"' % (dat, rate)) if rate else ""
    cyclone_levels = (cyclone or {}).get("levels") or []
    if cyclone_levels:
        cdat = os.path.join(results, "scale_cyclone.dat")
        write_scale_dat(cdat, cyclone_levels)
        extra += (', "%s" using 1:2 with linespoints lw 2 pt 5 title "Cyclone: handshakes/s", '
                       '"%s" using 1:4 axes x1y2 with linespoints lw 2 dt 4 '
                       'title "Cyclone: p99 (ms)", 20000 with lines dt 2 '
                       'title "Cyclone target: 20,000/s"' % (cdat, cdat))
    # Colours of their own: gnuplot's cycle would give the packed line the Fast DDS colour.
    for part, title, point, colour in (("inline", "inline steps", 9, "black"),
                                       ("packed", "inline, packed writes", 11, "#d95f02")):
        more = ((cyclone_modes or {}).get(part) or {}).get("levels") or []
        if more:
            mdat = os.path.join(results, "scale_cyclone_%s.dat" % part)
            write_scale_dat(mdat, more)
            extra += (', "%s" using 1:2 with linespoints lw 2 pt %d lc rgb "%s" '
                      'title "Cyclone, %s: handshakes/s"' % (mdat, point, colour, title))
    stem = os.path.join(results, "scaling")
    return [draw(stem, "Concurrent interface pairs between two processes "
                 "(Fast DDS SHM+UDP; Cyclone UDP)",
                 'set xlabel "interface pairs handshaking at once"\nset logscale x\n'
                 'set ylabel "handshakes per second"\nset y2label "latency (ms, log scale)"\n'
                 "set ytics nomirror\nset y2tics\nset grid\n"
                 "set key outside top center horizontal maxcols 3\n"
                 "set yrange [0:*]\nset logscale y2\n"
                 'plot "%s" using 1:2 with linespoints lw 2 pt 7 title "Fast DDS: handshakes/s", '
                 '"%s" using 1:3 axes x1y2 with linespoints lw 2 title "p50 (ms)", '
                 '"%s" using 1:4 axes x1y2 with linespoints lw 2 title "p99 (ms)"%s, '
                 '5000 with lines dt 2 title "target at 100 pairs: 5,000/s"\n'
                 % (dat, dat, dat, extra))]


# placement.png: (series in dds_latency*.json, label); the Cyclone round trip
# comes from its "cyclone" object.
PLACEMENT_SERIES = (
    ("udp_round_trip_2proc", "UDP round trip"),
    ("cyclone", "Cyclone round trip (ddsperf)"),
    ("raw_fastdds_listener_round_trip_shm_udp_2proc", "Fast DDS listener round trip"),
    ("mtc_handshake_shm_udp_2proc", "handshake, Fast DDS"),
    ("mtc_handshake_shm_udp_2proc_inline", "handshake, Fast DDS, inline"),
    ("mtc_handshake_cyclone_udp_loopback_2proc_inline", "handshake, Cyclone, inline"),
)


def placement_p50(latency, name):
    if name == "cyclone":
        return (latency.get("cyclone") or {}).get("p50")
    return next((s.get("p50") for s in latency.get("series", []) if s.get("name") == name), None)


def plot_placement(results, spread, one_cpu):
    rows = []
    for name, text in PLACEMENT_SERIES:
        a, b = placement_p50(spread, name), placement_p50(one_cpu, name)
        if a is not None and b is not None:
            rows.append((text, a, b))
    if not rows:
        return []
    dat = os.path.join(results, "placement.dat")
    with open(dat, "w") as f:
        f.write("# series p50_spread_us p50_one_cpu_us\n")
        for text, a, b in rows:
            f.write('"%s" %s %s\n' % (text, a, b))
    stem = os.path.join(results, "placement")
    return [draw(stem, "p50 latency, 2 processes: spread over the CPUs vs all on one CPU",
                 'set ylabel "microseconds"\nset style data histograms\n'
                 "set style histogram clustered gap 1\nset style fill solid 0.8 border -1\n"
                 "set boxwidth 0.9\nset grid ytics\nset key top left\nset yrange [0:*]\n"
                 "set xtics rotate by 20 right scale 0\nset bmargin 7\n"
                 'plot "%s" using 2:xtic(1) title "spread (the default)", '
                 '"" using 3 title "one CPU (--cpus)"\n' % dat)]


def load(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("results", help="the directory run.sh wrote the JSON files to")
    results = parser.parse_args().results
    if not shutil.which("gnuplot"):
        print("plot_summary.py: gnuplot not installed, no plots", file=sys.stderr)
        return 0
    written = []
    samples = load(os.path.join(results, "dds_latency_samples.json"))
    latency = load(os.path.join(results, "dds_latency.json")) or {}
    if samples:
        written += plot_cdfs(results, samples, latency.get("cyclone"))
    scale = load(os.path.join(results, "scale.json"))
    if scale:
        modes = {m: load(os.path.join(results, "scale_cyclone_%s.json" % m))
                 for m in ("inline", "packed")}
        written += plot_scale(results, scale, load(os.path.join(results, "scale_cyclone.json")),
                              modes)
    one_cpu = load(os.path.join(results, "dds_latency_one_cpu.json"))
    if latency and one_cpu:
        written += plot_placement(results, latency, one_cpu)
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())
