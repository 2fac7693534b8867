"""Matplotlib figures of the physics models, drawn from physics.accuracy_data.

One function per figure, each taking the data and a path; `write_all` makes the set that
`billiards diagrams OUTDIR` writes.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt

from physics import accuracy_data

#: Errors below this (mm) are drawn at it on the log axis (the reference's own error is 0).
ERROR_FLOOR_MM = 1e-4


def throw_figure(curves: list[dict[str, Any]], path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(7, 4.5))
    for c in curves:
        style = "-" if c["spin"] == "stun" else "--"
        ax.plot(c["cut_deg"], c["throw_deg"], style, label=f"{c['spin']}, {c['speed']:g} m/s")
    ax.set_xlabel("cut angle (degrees)")
    ax.set_ylabel("object ball throw (degrees)")
    ax.set_title("Ball-ball throw (Alciatore friction model)")
    ax.grid(alpha=0.3)
    ax.legend()
    return _save(fig, path)


def cushion_figure(curves: list[dict[str, Any]], path: Path) -> Path:
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.5))
    colours = {}
    for c in curves:
        colour = colours.setdefault(c["spin"], f"C{len(colours)}")
        style = "-" if c["model"] == "mathavan" else "--"
        label = f"{c['model']}, {c['spin']}"
        left.plot(c["incidence_deg"], c["rebound_deg"], style, color=colour, label=label)
        right.plot(c["incidence_deg"], c["speed_ratio"], style, color=colour, label=label)
    left.plot([0, 90], [0, 90], ":", color="grey", label="mirror reflection")
    left.set_xlabel("incidence angle from the normal (degrees)")
    left.set_ylabel("rebound angle from the normal (degrees)")
    right.set_xlabel("incidence angle from the normal (degrees)")
    right.set_ylabel("rebound speed / incoming speed")
    speed = curves[0]["speed"]
    fig.suptitle(f"Cushion rebound at {speed:g} m/s: Mathavan 2010 (solid) and Han 2005 (dashed)")
    for ax in (left, right):
        ax.grid(alpha=0.3)
    left.legend(fontsize=7)
    return _save(fig, path)


def motion_figure(profile: dict[str, Any], path: Path) -> Path:
    fig, ax = plt.subplots(figsize=(8, 4.5))
    t = profile["t"]
    ax.plot(t, profile["speed"], label="speed |v| (m/s)")
    ax.plot(t, profile["roll_surface_speed"], label="top/back spin as surface speed -R w_x (m/s)")
    spin_ax = ax.twinx()
    spin_ax.plot(t, profile["w_z"], color="C2", label="side spin w_z (rad/s)")
    spin_ax.set_ylabel("w_z (rad/s)")
    for time, kind in profile["events"]:
        ax.axvline(time, color="grey", ls=":", lw=1)
        ax.annotate(kind, (time, ax.get_ylim()[1]), rotation=90, va="top", fontsize=7)
    ax.set_xlabel("time (s)")
    ax.set_ylabel("m/s")
    ax.set_title("One ball through slide, roll and spin (Han 2005)")
    lines = ax.get_legend_handles_labels()
    more = spin_ax.get_legend_handles_labels()
    ax.legend(lines[0] + more[0], lines[1] + more[1], fontsize=8, loc="center right")
    ax.grid(alpha=0.3)
    return _save(fig, path)


def speed_error_figure(rows: list[dict[str, Any]], path: Path) -> Path:
    """Error (log) against CPU time (log): one point per method and shot."""
    fig, ax = plt.subplots(figsize=(9, 6))
    shots = list(dict.fromkeys(r["shot"] for r in rows))
    markers = {"event (reference)": "*", "event, cue ball +1e-9 m": "x"}
    for k, shot in enumerate(shots):
        colour = f"C{k}"
        fixed = [r for r in rows if r["shot"] == shot and r["method"].startswith("fixed")]
        ax.plot(
            [r["cpu_s"] for r in fixed],
            [max(r["rms_mm"], ERROR_FLOOR_MM) for r in fixed],
            "o-",
            color=colour,
            label=f"{shot}: fixed step (dt 1e-3 to 1e-5 s)",
        )
        for r in fixed:
            ax.annotate(
                r["method"].split("=")[1],
                (r["cpu_s"], max(r["rms_mm"], ERROR_FLOOR_MM)),
                fontsize=6,
                color=colour,
                xytext=(3, 3),
                textcoords="offset points",
            )
        for r in rows:
            if r["shot"] != shot or r["method"].startswith("fixed"):
                continue
            marker = markers.get(r["method"], "s")
            if marker == "s":
                short = r["method"].removeprefix("event ").removesuffix(" cushion")
                ax.annotate(
                    short,
                    (r["cpu_s"], r["rms_mm"]),
                    fontsize=6,
                    color=colour,
                    xytext=(4, -2),
                    textcoords="offset points",
                )
            ax.plot(
                r["cpu_s"],
                max(r["rms_mm"], ERROR_FLOOR_MM),
                marker,
                color=colour,
                ms=10 if marker == "*" else 6,
                mfc="none" if marker == "s" else colour,
            )
    for marker, what in (
        ("*", "event engine, the reference (error 0, drawn at the floor)"),
        ("s", "event engine, cheaper models"),
        ("x", "event engine, cue ball moved 1e-9 m (sensitivity)"),
    ):
        ax.plot([], [], marker, color="k", mfc="none" if marker == "s" else "k", label=what)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("CPU time per shot (s)")
    ax.set_ylabel("final-position error, RMS over balls (mm)")
    ax.set_title("Speed against error: event engine and fixed-step integration")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7, loc="lower right")
    return _save(fig, path)


def _save(fig, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def write_all(outdir: Path, rows: list[dict[str, Any]] | None = None) -> list[Path]:
    """Write the four figures into outdir; `rows` are speed-vs-error rows (measured here
    with the quicker step sizes when not given)."""
    outdir.mkdir(parents=True, exist_ok=True)
    if rows is None:
        rows = accuracy_data.speed_vs_error(steps=(1e-3, 2e-4, 5e-5), repeats=3)
    return [
        throw_figure(accuracy_data.throw_curves(), outdir / "throw.png"),
        cushion_figure(accuracy_data.rebound_curves(), outdir / "cushion_rebound.png"),
        motion_figure(accuracy_data.motion_profile(), outdir / "ball_motion.png"),
        speed_error_figure(rows, outdir / "speed_vs_error.png"),
    ]
