#!/usr/bin/env python3
"""Plots the summary of mtc-bench-dds-latency (or any JSON with a "series"
list of {name, p50, p90, p99, max}) as a PNG with gnuplot, or as an SVG
written here when gnuplot is absent. Standard library only. Prints the path
of the file it wrote.
"""
import argparse
import json
import shutil
import subprocess
import sys

PERCENTILES = ("p50", "p90", "p99")
COLOURS = ("#4e79a7", "#f28e2b", "#e15759")


def label(series):
    """Short two-line label: what was measured, then over which path."""
    metric = {
        "round_trip": "raw Fast DDS RTT",
        "transition": "mtc transition",
        "handshake": "mtc handshake",
    }.get(series.get("metric", ""), series.get("name", "?"))
    transport = {"udp_loopback": "UDP", "shm_udp": "SHM+UDP"}.get(
        series.get("transport", ""), series.get("transport", ""))
    stepping = series.get("stepping", "-")
    mode = ", " + stepping if stepping in ("inline", "executor") else ""
    return "%s\\n%s, %s proc%s" % (metric, transport, series.get("processes", "?"), mode)


ORDER = {"round_trip": 0, "transition": 1, "handshake": 2}


def ordered(summary):
    """Like with like: raw round trips, then transitions, then handshakes."""
    return sorted(summary["series"], key=lambda s: (ORDER.get(s.get("metric"), 9),
                                                   s.get("processes", 0),
                                                   s.get("transport", "")))


def write_gnuplot(summary, stem):
    series = ordered(summary)
    dat = stem + ".dat"
    with open(dat, "w") as f:
        f.write("# label p50 p90 p99 max (microseconds)\n")
        for s in series:
            f.write('"%s" %s %s %s %s\n' % (label(s), s["p50"], s["p90"], s["p99"], s["max"]))
    title = ("mtconnect-dds latency, one run on %s cores, same QoS preset (log scale; "
             "p50 printed)\\nRTT = two one-way transits; transition = one change seen by the "
             "peer's state machine; handshake = Table 1 steps 1-8") % summary.get("cores", "?")
    script = stem + ".gp"
    with open(script, "w") as f:
        f.write('set terminal pngcairo size 1400,700 font "sans,11"\n'
                if gnuplot_has("pngcairo") else 'set terminal png size 1400,700\n')
        f.write('set output "%s.png"\n' % stem)
        f.write('set title "%s"\n' % title)
        f.write('set ylabel "latency (microseconds)"\n')
        f.write("set logscale y\nset grid ytics mytics\nset key top left\n")
        f.write("set style data histogram\nset style histogram clustered gap 1\n")
        f.write("set style fill solid 0.9 border -1\nset boxwidth 0.9\n")
        f.write("set xtics nomirror font \",9\"\nset bmargin 5\n")
        f.write("set yrange [10:*]\n")
        plots = []
        for i, p in enumerate(PERCENTILES):
            xt = ":xtic(1)" if i == 0 else ""
            plots.append('"%s" using %d%s title "%s" lc rgb "%s"' % (dat, i + 2, xt, p, COLOURS[i]))
        # max as points over each cluster: x of cluster k is k (0-based).
        plots.append('"%s" using ($0):5 with points pt 7 ps 1.2 lc rgb "black" title "max"' % dat)
        plots.append('"%s" using ($0-0.3):2:(sprintf("%%.0f",$2)) with labels offset 0,0.8 '
                     'font ",9" notitle' % dat)
        f.write("plot " + ", \\\n     ".join(plots) + "\n")
    subprocess.run(["gnuplot", script], check=True)
    return stem + ".png"


def gnuplot_has(terminal):
    try:
        out = subprocess.run(["gnuplot", "-e", "set terminal"], capture_output=True, text=True)
    except OSError:
        return False
    return terminal in (out.stdout + out.stderr)


def write_svg(summary, stem):
    """Fallback without gnuplot: a plain log-scale grouped bar chart."""
    import math
    series = ordered(summary)
    width, height, left, bottom, top = 1400, 700, 80, 120, 50
    plot_h = height - bottom - top
    values = [s[k] for s in series for k in PERCENTILES + ("max",) if s.get(k, 0) > 0]
    lo, hi = 0, math.ceil(math.log10(max(values + [10])))

    def y(v):
        v = max(v, 1.0)
        return top + plot_h * (1 - (math.log10(v) - lo) / (hi - lo))

    group_w = (width - left - 20) / max(len(series), 1)
    bar_w = group_w * 0.8 / len(PERCENTILES)
    out = ['<svg xmlns="http://www.w3.org/2000/svg" width="%d" height="%d" '
           'font-family="sans-serif" font-size="12">' % (width, height),
           '<rect width="100%" height="100%" fill="white"/>',
           '<text x="%d" y="25" font-size="16">mtconnect-dds latency (microseconds, log scale)'
           '</text>' % left]
    for e in range(lo, hi + 1):
        out.append('<line x1="%d" x2="%d" y1="%.1f" y2="%.1f" stroke="#ccc"/>'
                   % (left, width - 20, y(10 ** e), y(10 ** e)))
        out.append('<text x="%d" y="%.1f" text-anchor="end">%g</text>' % (left - 5, y(10 ** e) + 4, 10 ** e))
    for i, s in enumerate(series):
        x0 = left + i * group_w + group_w * 0.1
        for j, k in enumerate(PERCENTILES):
            top_y = y(s[k])
            out.append('<rect x="%.1f" y="%.1f" width="%.1f" height="%.1f" fill="%s"/>'
                       % (x0 + j * bar_w, top_y, bar_w, top + plot_h - top_y, COLOURS[j]))
        out.append('<circle cx="%.1f" cy="%.1f" r="4" fill="black"/>'
                   % (x0 + 1.5 * bar_w, y(s["max"])))
        for n, line in enumerate(label(s).split("\\n")):
            out.append('<text x="%.1f" y="%d" text-anchor="middle">%s</text>'
                       % (x0 + 1.5 * bar_w, height - bottom + 20 + 15 * n, line))
    for j, k in enumerate(PERCENTILES + ("max",)):
        colour = COLOURS[j] if j < len(COLOURS) else "black"
        out.append('<rect x="%d" y="%d" width="12" height="12" fill="%s"/><text x="%d" y="%d">%s</text>'
                   % (left + 10 + 70 * j, 40, colour, left + 26 + 70 * j, 51, k))
    out.append("</svg>")
    with open(stem + ".svg", "w") as f:
        f.write("\n".join(out))
    return stem + ".svg"


def main(argv):
    parser = argparse.ArgumentParser(
        prog="plot_latency.py", description=__doc__,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("summary", help="the JSON summary (mtc-bench-dds-latency --out FILE)")
    parser.add_argument("stem", help="output path without extension: <stem>.png or <stem>.svg")
    args = parser.parse_args(argv[1:])  # usage errors: exit 2
    try:
        with open(args.summary) as f:
            summary = json.load(f)
    except (OSError, ValueError) as error:
        print("plot_latency.py: cannot read %s: %s" % (args.summary, error), file=sys.stderr)
        return 1
    if not isinstance(summary, dict) or not summary.get("series"):
        print("plot_latency.py: no series in %s" % args.summary, file=sys.stderr)
        return 1
    if shutil.which("gnuplot"):
        path = write_gnuplot(summary, args.stem)
    else:
        path = write_svg(summary, args.stem)
    print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
