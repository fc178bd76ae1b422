#!/usr/bin/python3
"""Plots of the accuracy report, drawn from the JSON results marchcheck report writes.

usage: plots.py DATA_DIR PLOTS_DIR
Reads DATA_DIR/{sweep-steps,sweep-normals,sweep-shadow,convergence,grazing}.json and writes one PNG per plot.
"""
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")  # no display: the report is built headless
import matplotlib.pyplot as plt  # noqa: E402


def load(data_dir, name):
    with open(os.path.join(data_dir, name + ".json"), encoding="utf-8") as f:
        return json.load(f)


def save(fig, plots_dir, name):
    fig.tight_layout()
    fig.savefig(os.path.join(plots_dir, name + ".png"), dpi=110)
    plt.close(fig)


def metric(point, name):
    value = point["metrics"].get(name)
    return math.nan if value is None else value


def pareto(sweep, plots_dir):
    """Error against evaluations for every combination, the Pareto front joined."""
    err = sweep["error_metric"]
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    groups = {}
    for p in sweep["points"]:
        label = ", ".join(f"{k}={v}" for k, v in p["settings"].items() if k != "max_steps")
        groups.setdefault(label or "all", []).append(p)
    for label, points in groups.items():
        xs = [metric(p, "cost.evals_per_pixel") for p in points]
        ys = [metric(p, err) for p in points]
        ax.plot(xs, ys, "o-", alpha=0.7, label=label)
        for p, x, y in zip(points, xs, ys):
            ax.annotate(str(p["settings"].get("max_steps", "")), (x, y), fontsize=7, xytext=(3, 3),
                        textcoords="offset points")
    front = sorted((p for p in sweep["points"] if p["pareto_evals"]), key=lambda p: metric(p, "cost.evals_per_pixel"))
    ax.plot([metric(p, "cost.evals_per_pixel") for p in front], [metric(p, err) for p in front], "k--", lw=1,
            label="Pareto front")
    ax.set_xlabel("SDF evaluations per pixel")
    ax.set_ylabel(err)
    ax.set_yscale("log")
    ax.set_title(f"{sweep['scene']}: error against cost (labels: max_steps)")
    ax.legend(fontsize=8)
    save(fig, plots_dir, "pareto")


def convergence(conv, plots_dir):
    """Decided fraction against max_steps, one line per scene."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for scene, rows in conv.items():
        ax.plot([r["max_steps"] for r in rows], [r["decided"] for r in rows], "o-", label=scene)
    ax.set_xscale("log", base=2)
    ax.set_xlabel("max_steps")
    ax.set_ylabel("fraction of rays decided (hit or miss)")
    ax.set_ylim(0, 1.02)
    ax.set_title("Convergence against the step limit")
    ax.legend(fontsize=8)
    save(fig, plots_dir, "convergence")


def normals(sweep, plots_dir):
    """Normal error p99 against the difference epsilon, one line per method."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    methods = {}
    for p in sweep["points"]:
        methods.setdefault(p["settings"]["normal"], []).append(p)
    for method, points in methods.items():
        xs = [float(p["settings"]["normal_eps"]) for p in points]
        ax.plot(xs, [metric(p, "normal.angle_p99_deg") for p in points], "o-", label=method)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("normal_eps")
    ax.set_ylabel("normal.angle_p99_deg")
    ax.set_title(f"{sweep['scene']}: normal error against epsilon")
    ax.legend(fontsize=8)
    save(fig, plots_dir, "normals")


def shadows(sweep, plots_dir):
    """False shadow (acne) and false lit (leaks) per bias strategy."""
    points = sweep["points"]
    labels = [p["settings"]["shadow_bias"] for p in points]
    xs = range(len(points))
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    width = 0.38
    ax.bar([x - width / 2 for x in xs], [metric(p, "shadow.false_shadow") for p in points], width,
           label="shadow.false_shadow (acne)")
    ax.bar([x + width / 2 for x in xs], [metric(p, "shadow.false_lit") for p in points], width,
           label="shadow.false_lit (leaks)")
    ax.set_xticks(list(xs), labels)
    ax.set_ylabel("fraction of reference points")
    ax.set_title(f"{sweep['scene']}: shadow errors per bias strategy")
    ax.legend(fontsize=8)
    save(fig, plots_dir, "shadows")


def grazing(rows, plots_dir):
    """Steps a grazing ray needs against the pi * sqrt(2R/b) law."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    bs = [r["clearance"] for r in rows]
    ax.plot(bs, [r["steps"] for r in rows], "o", label="sphere tracing (measured)")
    ax.plot(bs, [r["law"] for r in rows], "-", label="π·sqrt(2R/b)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("clearance b (R = 1)")
    ax.set_ylabel("steps to pass the sphere")
    ax.set_title("Grazing rays")
    ax.legend(fontsize=8)
    save(fig, plots_dir, "grazing")


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    data_dir, plots_dir = sys.argv[1], sys.argv[2]
    os.makedirs(plots_dir, exist_ok=True)
    pareto(load(data_dir, "sweep-steps"), plots_dir)
    convergence(load(data_dir, "convergence"), plots_dir)
    normals(load(data_dir, "sweep-normals"), plots_dir)
    shadows(load(data_dir, "sweep-shadow"), plots_dir)
    grazing(load(data_dir, "grazing"), plots_dir)


if __name__ == "__main__":
    main()
