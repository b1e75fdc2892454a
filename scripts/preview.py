#!/usr/bin/python3
"""Renders a cellform output directory (cells.ply, veins.ply) to a PNG preview.

usage: scripts/preview.py OUT_DIR [PNG] [--top] [--elev DEG] [--azim DEG] [--dpi N]
Needs Debian's python3-matplotlib (apt-get install python3-matplotlib).
"""
import argparse
import os
import struct
import sys
from pathlib import Path

plt = Line3DCollection = Poly3DCollection = None  # matplotlib, imported once the command line is read


def load_matplotlib():
    """Imports matplotlib (after the arguments: --help and a bad command line need none)."""
    global plt, Line3DCollection, Poly3DCollection
    try:
        import matplotlib
    except ImportError:
        other = sys.prefix != sys.base_prefix or os.path.realpath(sys.executable) != os.path.realpath("/usr/bin/python3")
        if other and os.path.exists("/usr/bin/python3"):  # a virtual environment, or another Python
            sys.exit("preview.py needs matplotlib, which this Python (" + sys.executable + ") cannot import: "
                     "run it as scripts/preview.py (it starts Debian's /usr/bin/python3), or install matplotlib "
                     "for this Python")
        sys.exit("preview.py needs Debian's python3-matplotlib, which is not installed: "
                 "sudo apt-get install python3-matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as pyplot
    from mpl_toolkits.mplot3d import art3d
    plt, Line3DCollection, Poly3DCollection = pyplot, art3d.Line3DCollection, art3d.Poly3DCollection

TYPES = {"char": "b", "uchar": "B", "short": "h", "ushort": "H", "int": "i", "uint": "I", "float": "f", "double": "d",
         "int8": "b", "uint8": "B", "int32": "i", "uint32": "I", "float32": "f", "float64": "d"}


def read_ply(path):
    data = Path(path).read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    elements = []
    for line in data[:end].decode().splitlines():
        w = line.split()
        if w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property":
            elements[-1][2].append(w[1:])
    out = {}
    if b"format ascii" in data[:end]:  # PLY from elsewhere (cellform writes binary)
        words = iter(data[end:].split())
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for p in props:
                    cast = float if p[-2] in ("float", "double", "float32", "float64") else int
                    if p[0] == "list":
                        row[p[3]] = tuple(cast(next(words)) for _ in range(int(next(words))))
                    else:
                        row[p[1]] = cast(next(words))
                rows.append(row)
            out[name] = rows
        return out
    pos = end
    for name, count, props in elements:
        rows = []
        for _ in range(count):
            row = {}
            for p in props:
                if p[0] == "list":
                    (n,) = struct.unpack_from("<" + TYPES[p[1]], data, pos)
                    pos += struct.calcsize(TYPES[p[1]])
                    fmt = "<%d%s" % (n, TYPES[p[2]])
                    row[p[3]] = struct.unpack_from(fmt, data, pos)
                    pos += struct.calcsize(fmt)
                else:
                    fmt = "<" + TYPES[p[0]]
                    (row[p[1]],) = struct.unpack_from(fmt, data, pos)
                    pos += struct.calcsize(fmt)
            rows.append(row)
        out[name] = rows
    return out


def top_view(fig, cells, v, bounds, out_dir, png):  # noqa: C901
    """Orthographic view from +z: the sheet in green, veins in brown with widths by radius."""
    from matplotlib.collections import LineCollection, PolyCollection
    ax = fig.add_subplot()
    polys = [[v[i][:2] for i in f["vertex_indices"]] for f in cells.get("face", [])]
    ax.add_collection(PolyCollection(polys, facecolor=(0.6, 0.8, 0.5, 0.5), edgecolor=(0.3, 0.5, 0.3, 0.3),
                                     linewidths=0.2))
    xs, ys, _ = zip(*bounds)
    points_per_unit = 0.9 * 72 * fig.get_figwidth() / max(max(xs) - min(xs) + 2, max(ys) - min(ys) + 2)
    veins = out_dir / "veins.ply"
    if veins.exists():
        g = read_ply(veins)
        vv = g["vertex"]
        segs, widths = [], []
        for e in g.get("edge", []):
            a, b = vv[e["vertex1"]], vv[e["vertex2"]]
            segs.append([(a["x"], a["y"]), (b["x"], b["y"])])
            widths.append(max(0.3, 2 * min(a["radius"], b["radius"]) * points_per_unit))
        ax.add_collection(LineCollection(segs, colors=[(0.45, 0.1, 0.05)], linewidths=widths, capstyle="round"))
    ax.set_xlim(min(xs) - 1, max(xs) + 1)
    ax.set_ylim(min(ys) - 1, max(ys) + 1)
    ax.set_aspect("equal")
    ax.set_axis_off()
    save(fig, png)


def save(fig, png):
    """Writes the PNG, or stops with one line saying why it cannot."""
    try:
        fig.tight_layout()
        fig.savefig(png)
    except OSError as e:
        sys.exit(f"preview.py: cannot write '{png}': {e.strerror or e}")
    print(png)


def positive_int(text):
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{text}' is not a whole number")
    if n < 1 or n > 2000:
        raise argparse.ArgumentTypeError(f"{n} is not from 1 to 2000")
    return n


def main():
    parser = argparse.ArgumentParser(
        prog="preview.py", description="Renders a cellform output folder (cells.ply, veins.ply) to a PNG.",
        allow_abbrev=False)
    parser.add_argument("out_dir", metavar="OUT_DIR", help="a cellform output folder")
    parser.add_argument("png", metavar="PNG", nargs="?", help="the PNG to write (default: OUT_DIR/preview.png)")
    parser.add_argument("--top", action="store_true", help="orthographic view from +z")
    parser.add_argument("--elev", type=float, default=35, metavar="DEG", help="3-D view: elevation (default 35)")
    parser.add_argument("--azim", type=float, default=-60, metavar="DEG", help="3-D view: azimuth (default -60)")
    parser.add_argument("--dpi", type=positive_int, default=100, metavar="N", help="dots per inch of the 8-inch "
                        "square image (default 100)")
    opts = parser.parse_args()
    load_matplotlib()
    out_dir = Path(opts.out_dir)
    png = Path(opts.png) if opts.png else out_dir / "preview.png"
    # a cell run has cells.ply (and veins.ply with venation{}); space colonisation in a leaf or a volume
    # has only veins.ply
    if not out_dir.is_dir():
        sys.exit(f"preview.py: '{out_dir}' is not a folder" + (" (it does not exist)" if not out_dir.exists() else "")
                 + ": give a cellform output folder")
    if not (out_dir / "cells.ply").exists() and not (out_dir / "veins.ply").exists():
        sys.exit(f"preview.py: '{out_dir}' holds neither cells.ply nor veins.ply: give a cellform output folder")
    cells = read_ply(out_dir / "cells.ply") if (out_dir / "cells.ply").exists() else {"vertex": []}
    v = [(r["x"], r["y"], r["z"]) for r in cells["vertex"]]
    faces = [[v[i] for i in f["vertex_indices"]] for f in cells.get("face", [])]
    if (out_dir / "veins.ply").exists():  # the view's bounds hold the veins too
        vein_points = [(r["x"], r["y"], r["z"]) for r in read_ply(out_dir / "veins.ply")["vertex"]]
    else:
        vein_points = []
    bounds = v + vein_points or [(0.0, 0.0, 0.0)]
    fig = plt.figure(figsize=(8, 8), dpi=opts.dpi)
    if opts.top:
        return top_view(fig, cells, v, bounds, out_dir, png)
    ax = fig.add_subplot(projection="3d")
    ax.add_collection3d(Poly3DCollection(faces, facecolor=(0.55, 0.75, 0.45, 0.55), edgecolor=(0.2, 0.35, 0.2, 0.25),
                                         linewidths=0.2))
    xs, ys, zs = zip(*bounds)
    c = [(max(t) + min(t)) / 2 for t in (xs, ys, zs)]
    r = max(max(t) - min(t) for t in (xs, ys, zs)) / 2 or 1
    points_per_unit = 0.9 * 72 * fig.get_figwidth() / (2 * r)  # about: the view is a cube of side 2 r
    veins = out_dir / "veins.ply"
    if veins.exists():  # one collection: a line per edge took minutes for 190,000 nodes
        g = read_ply(veins)
        vv = g["vertex"]
        segs, widths = [], []
        for e in g.get("edge", []):
            a, b = vv[e["vertex1"]], vv[e["vertex2"]]
            segs.append([(a["x"], a["y"], a["z"]), (b["x"], b["y"], b["z"])])
            widths.append(max(0.3, 2 * min(a["radius"], b["radius"]) * points_per_unit))
        ax.add_collection3d(Line3DCollection(segs, colors=[(0.45, 0.1, 0.05)], linewidths=widths))
    ax.set_xlim(c[0] - r, c[0] + r)
    ax.set_ylim(c[1] - r, c[1] + r)
    ax.set_zlim(c[2] - r, c[2] + r)
    ax.view_init(elev=opts.elev, azim=opts.azim)
    ax.set_axis_off()
    save(fig, png)


if __name__ == "__main__":
    main()
