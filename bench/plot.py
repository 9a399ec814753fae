#!/usr/bin/python3
"""Plot a benchmark CSV as a PNG: one line (or scatter) per group, optional log axes.

Every "what accuracy costs in time" chart in geom goes through this one script, so the
charts look alike and a benchmark only has to write a CSV (bench/support/harness.h Table).

  bench/plot.py bench-out/lod_tradeoff.csv --x seconds --y hausdorff --group method \
      --logx --logy --title "LOD: error against time" -o bench-out/lod_tradeoff.png

Columns are named as in the CSV header. Rows whose x or y is not a number are skipped
(a peer that did not run writes "n/a"). Needs Debian's python3-matplotlib.
"""
import argparse
import csv
import sys


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def number(text):
    try:
        v = float(text.rstrip("x"))
    except (AttributeError, ValueError):
        return None
    return v if v == v else None  # NaN counts as missing


def series(rows, x, y, group):
    out = {}
    for row in rows:
        for col in (x, y) + ((group,) if group else ()):
            if col not in row:
                sys.exit(f"plot.py: column '{col}' not in CSV (have: {', '.join(row)})")
        xv, yv = number(row[x]), number(row[y])
        if xv is None or yv is None:
            continue
        out.setdefault(row[group] if group else y, []).append((xv, yv))
    return out


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("csv")
    p.add_argument("--x", required=True, help="column for the x axis")
    p.add_argument("--y", required=True, help="column for the y axis")
    p.add_argument("--group", help="column whose values name the lines")
    p.add_argument("--logx", action="store_true")
    p.add_argument("--logy", action="store_true")
    p.add_argument("--scatter", action="store_true", help="markers only, no lines")
    p.add_argument("--title", default="")
    p.add_argument("--xlabel")
    p.add_argument("--ylabel")
    p.add_argument("-o", "--output", required=True, help="PNG path")
    a = p.parse_args(argv)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    data = series(read_rows(a.csv), a.x, a.y, a.group)
    if not data:
        sys.exit(f"plot.py: {a.csv}: no numeric rows for {a.x} / {a.y}")
    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=120)
    for name, pts in data.items():
        pts.sort()
        xs, ys = zip(*pts)
        ax.plot(xs, ys, "o" if a.scatter else "o-", label=name, markersize=4)
    if a.logx:
        ax.set_xscale("log")
    if a.logy:
        ax.set_yscale("log")
    ax.set_xlabel(a.xlabel or a.x)
    ax.set_ylabel(a.ylabel or a.y)
    ax.set_title(a.title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(a.output)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
