#!/usr/bin/env python3
"""usage: plot.py <summary.json> <output.png>

Plots CPU and RSS over time, one line per process, from the JSON of
benchmarks/endurance (endurance.py or mtc-bench-idle) with gnuplot.
Standard library only; exits 1 with a message when gnuplot is missing.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile


def write_data(processes, directory):
    """One whitespace-separated file per process: minutes, CPU %, RSS MiB."""
    files = []
    for i, p in enumerate(processes):
        path = os.path.join(directory, "p%d.dat" % i)
        with open(path, "w") as f:
            f.write("# minutes cpu_pct rss_mib (%s)\n" % p["name"])
            for s in p.get("samples", []):
                cpu = s.get("cpu_pct")
                f.write("%.4f %s %.3f\n" % (s["t_s"] / 60.0, "?" if cpu is None else cpu,
                                            s["rss_kb"] / 1024.0))
        files.append((p["name"], path))
    return files


def gnuplot_script(summary, files, png):
    title = summary.get("title") or summary.get("benchmark", "endurance")
    lines = [
        'set terminal pngcairo size 1200,900 font "sans,10"',
        'set output "%s"' % png,
        "set datafile missing '?'",
        "set multiplot layout 2,1 title \"%s\"" % title.replace('"', "'"),
        "set grid",
        "set key outside right top",
        "set xlabel 'minutes since start'",
        "set ylabel 'CPU (% of one core, per sample interval)'",
        "set yrange [0:*]",
    ]
    cpu = ", ".join("'%s' using 1:2 with linespoints pt 7 ps 0.4 title '%s'" % (path, name)
                    for name, path in files)
    rss = ", ".join("'%s' using 1:3 with linespoints pt 7 ps 0.4 title '%s'" % (path, name)
                    for name, path in files)
    lines += ["plot " + cpu, "set ylabel 'RSS (MiB)'", "plot " + rss, "unset multiplot"]
    return "\n".join(lines) + "\n"


def plot(summary, png):
    """Writes `png`; returns None, or the reason it could not."""
    gnuplot = shutil.which("gnuplot")
    if not gnuplot:
        return "gnuplot not found (scripts/setup-deps.sh installs gnuplot-nox)"
    processes = [p for p in summary.get("processes", []) if p.get("samples")]
    if not processes:
        return "no samples to plot"
    with tempfile.TemporaryDirectory(prefix="mtc-endurance-plot-") as tmp:
        files = write_data(processes, tmp)
        script = os.path.join(tmp, "plot.gp")
        with open(script, "w") as f:
            f.write(gnuplot_script(summary, files, png))
        done = subprocess.run([gnuplot, script], capture_output=True, text=True)
        if done.returncode != 0:
            return "gnuplot failed: " + done.stderr.strip()
    return None


def main(argv):
    if len(argv) == 2 and argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0
    if len(argv) != 3 or argv[1].startswith("-"):
        sys.stderr.write(__doc__.strip() + "\n")
        return 2
    with open(argv[1]) as f:
        summary = json.load(f)
    problem = plot(summary, argv[2])
    if problem:
        sys.stderr.write("plot.py: %s\n" % problem)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
