#!/usr/bin/env python3
"""Draws R1's work-precision plot (orientation error against run time, log-log) as SVG.

Reads bench/results/r1_work_precision.csv (written by bench_r1_work_precision) and puts the
anchors' measured figures (../shared/anchors/README.md, copied below with their source) beside
simreel's. Standard library only, so it runs on a bare Debian 12.

    python3 bench/plot_work_precision.py [CSV] [SVG]
"""
import csv
import math
import sys

CSV = sys.argv[1] if len(sys.argv) > 1 else "bench/results/r1_work_precision.csv"
SVG = sys.argv[2] if len(sys.argv) > 2 else "bench/results/r1_work_precision.svg"
DURATION = 20.0  # s, R1's simulated time

# Anchors, R1: (label, us per step, {dt_inv: max orientation error in rad}).
ANCHORS = [
    ("MuJoCo RK4", 3.19, {60: 1.7e-3, 240: 1.0e-4, 3840: 4.1e-7}),
    ("Bullet f64 default", 1.16, {60: 3.14, 240: 1.45, 3840: 0.093}),
    ("ODE, gyroscopic", 0.40, {60: 3.14, 240: 3.14, 3840: 3.14}),
]
COLORS = {"auto": "#d62728", "rk4": "#ff7f0e", "splitting": "#2ca02c", "euler_gyro": "#1f77b4",
          "seed": "#7f7f7f", "MuJoCo RK4": "#9467bd", "Bullet f64 default": "#8c564b",
          "ODE, gyroscopic": "#e377c2"}

series = {}
with open(CSV) as f:
    rows = [r for r in csv.DictReader(line for line in f if not line.startswith("#"))]
for r in rows:
    t = float(r["wall_s_min"])
    e = max(float(r["max_orient_err_rad"]), 1e-12)
    series.setdefault(r["integrator"], []).append((t, e))

W, H, L, R, T, B = 760, 480, 70, 190, 30, 50
X0, X1, Y0, Y1 = -6, 0, -10, 1  # decades


def px(t):
    return L + (math.log10(t) - X0) / (X1 - X0) * (W - L - R)


def py(e):
    return T + (Y1 - math.log10(e)) / (Y1 - Y0) * (H - T - B)


out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{W}" height="{H}" font-family="sans-serif" font-size="12">',
       f'<rect width="{W}" height="{H}" fill="white"/>']
for d in range(X0, X1 + 1):
    x = px(10.0 ** d)
    out.append(f'<line x1="{x:.1f}" y1="{T}" x2="{x:.1f}" y2="{H - B}" stroke="#ddd"/>')
    out.append(f'<text x="{x:.1f}" y="{H - B + 16}" text-anchor="middle">1e{d}</text>')
for d in range(Y0, Y1 + 1):
    y = py(10.0 ** d)
    out.append(f'<line x1="{L}" y1="{y:.1f}" x2="{W - R}" y2="{y:.1f}" stroke="#ddd"/>')
    out.append(f'<text x="{L - 6}" y="{y + 4:.1f}" text-anchor="end">1e{d}</text>')
out.append(f'<rect x="{L}" y="{T}" width="{W - L - R}" height="{H - T - B}" fill="none" stroke="black"/>')
out.append(f'<text x="{(L + W - R) / 2}" y="{H - 12}" text-anchor="middle">run time for 20 s of R1 (s, one core)</text>')
out.append(f'<text transform="translate(16 {(T + H - B) / 2}) rotate(-90)" text-anchor="middle">'
           'max orientation error (rad)</text>')
out.append(f'<text x="{L}" y="{T - 10}">R1: box tumbling about its intermediate axis; dt = 1/30 ... 1/3840</text>')


def draw(name, pts, dashed, marker):
    c = COLORS.get(name, "black")
    pts = sorted(pts)
    path = " ".join(f"{px(t):.1f},{py(e):.1f}" for t, e in pts)
    dash = ' stroke-dasharray="5,3"' if dashed else ""
    out.append(f'<polyline points="{path}" fill="none" stroke="{c}" stroke-width="2"{dash}/>')
    for t, e in pts:
        if marker == "circle":
            out.append(f'<circle cx="{px(t):.1f}" cy="{py(e):.1f}" r="3" fill="{c}"/>')
        else:
            out.append(f'<rect x="{px(t) - 3.5:.1f}" y="{py(e) - 3.5:.1f}" width="7" height="7" fill="{c}"/>')


legend = []
for name in ["auto", "rk4", "splitting", "euler_gyro", "seed"]:
    if name in series:
        draw(name, series[name], False, "circle")
        legend.append((("simreel " + name + (" (default)" if name == "auto" else "")), name, False))
for name, us, errs in ANCHORS:
    draw(name, [(us * 1e-6 * DURATION * n, e) for n, e in errs.items()], True, "square")
    legend.append((name + " (anchor)", name, True))
for i, (text, key, dashed) in enumerate(legend):
    y = T + 14 + 18 * i
    dash = ' stroke-dasharray="5,3"' if dashed else ""
    out.append(f'<line x1="{W - R + 12}" y1="{y - 4}" x2="{W - R + 34}" y2="{y - 4}" stroke="{COLORS[key]}" '
               f'stroke-width="2"{dash}/>')
    out.append(f'<text x="{W - R + 40}" y="{y}">{text}</text>')
out.append("</svg>")
with open(SVG, "w") as f:
    f.write("\n".join(out) + "\n")
print(f"wrote {SVG}")
