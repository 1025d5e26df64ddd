"""Figures of an evaluation (`fmcw evaluate` / `fmcw run`): the paper's Table II and Fig. 5-9; the tables."""

import os

import matplotlib.pyplot as plt
import numpy as np
from evaluation_snapshot import figure_bev, figure_range_image
from report_common import method_colour, method_style, read_table, save_figure, select

# Table II of the paper, for the scenarios that reproduce its datasets.
PAPER_TABLE2 = {
    "intersection": ("intersection", 135, 473271, 13.5, "Stationary"),
    "t_intersection": ("T-intersection", 98, 463957, 9.8, "Stationary"),
    "straight_road": ("Straight road", 91, 122893, 9.1, "Moving"),
    "turn_and_straight_road": ("Turn & Straight road", 151, 1256177, 15.1, "Moving"),
}


class EvaluationData:
    """The tables of one evaluation folder, split by method."""

    def __init__(self, out_dir, metrics):
        self.dir = out_dir
        self.metrics = metrics
        self.methods = metrics["method_order"]
        files = metrics["files"]
        frames = read_table(os.path.join(out_dir, files["frames"]))
        objects = read_table(os.path.join(out_dir, files["objects"]))
        self.frames = {m: select(frames, frames["method"] == m) for m in self.methods}
        self.objects = {m: select(objects, objects["method"] == m) for m in self.methods}
        self.pixels = read_table(os.path.join(out_dir, files["snapshot_pixels"]))
        self.clusters = read_table(os.path.join(out_dir, files["snapshot_clusters"]))
        self.actors = read_table(os.path.join(out_dir, files["snapshot_actors"]))
        self.rate_hz = metrics["dataset"]["rate_hz"]
        default = metrics["default_method"]
        self.default = default if default in self.methods else self.methods[-1]

    def time_s(self, method):
        return self.frames[method]["frame"] / self.rate_hz

    def identical_groups(self):
        """Groups of methods whose per-frame TP and FP counts agree everywhere (same labels)."""
        groups = []
        for m in self.methods:
            f = self.frames[m]
            for g in groups:
                r = self.frames[g[0]]
                if np.array_equal(f["tp"], r["tp"]) and np.array_equal(f["fp"], r["fp"]):
                    g.append(m)
                    break
            else:
                groups.append([m])
        return [g for g in groups if len(g) > 1]


def _legend_note(data):
    groups = data.identical_groups()
    if not groups:
        return ""
    return "\n(identical labels, lines overlap: " + "; ".join(" = ".join(g) for g in groups) + ")"


def figure_dataset(data):
    """Table II analogue: scans, motion points, duration, ego motion; per-frame detail beside it."""
    d = data.metrics["dataset"]
    scenario = data.metrics["scenario"]
    fig = plt.figure(figsize=(12, 3.6))
    ax_t = fig.add_axes([0.0, 0.05, 0.38, 0.85])
    ax_t.axis("off")
    rows = [["Scans", f"{d['scans']}"], ["Motion points (total)", f"{d['motion_points']:,}"],
            ["Time", f"{d['duration_s']:.1f} s"], ["Movement status", d["ego_status"].capitalize()],
            ["Max ego speed", f"{d['max_ego_speed_mps']:.1f} m/s"], ["Actors seen", f"{d['actors_seen']}"]]
    columns = ["", "this dataset"]
    if scenario in PAPER_TABLE2:
        name, scans, points, t, status = PAPER_TABLE2[scenario]
        paper = [f"{scans}", f"{points:,}", f"{t:.1f} s", status, "–", "–"]
        rows = [r + [p] for r, p in zip(rows, paper)]
        columns.append(f"paper ({name})")
    widths = [0.34, 0.26, 0.40] if len(columns) == 3 else [0.5, 0.5]
    table = ax_t.table(cellText=rows, colLabels=columns, loc="center", cellLoc="left", colLoc="left",
                       colWidths=widths)
    table.auto_set_font_size(False)
    table.set_fontsize(9.5)
    table.scale(1.0, 1.5)
    for (r, _), cell in table.get_celld().items():
        if r == 0:
            cell.set_text_props(weight="bold")
            cell.set_facecolor("#eeeeee")
    ax_t.set_title(f"Dataset '{scenario}' (the paper's Table II)", fontsize=11, y=0.92)

    ax = fig.add_axes([0.47, 0.15, 0.45, 0.72])
    f = data.frames[data.methods[0]]
    t = data.time_s(data.methods[0])
    ax.bar(t, f["truth_moving"], width=0.8 / data.rate_hz, color="#9ecae1", label="truly moving points")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("truly moving points per scan")
    ax2 = ax.twinx()
    speed = np.sqrt(f["true_vx_mps"] ** 2 + f["true_vy_mps"] ** 2 + f["true_vz_mps"] ** 2)
    ax2.plot(t, speed, color="#d62728", lw=2.0, label="ego speed", zorder=5)
    ax2.set_ylabel("ego speed [m/s]", color="#d62728")
    ax2.set_ylim(0, max(1.0, speed.max() * 1.15))
    ax2.grid(False)
    ax2.spines["right"].set_visible(True)
    handles = ax.get_legend_handles_labels()[0] + ax2.get_legend_handles_labels()[0]
    ax.legend(handles, [h.get_label() for h in handles], loc="upper left")
    ax.set_title("Moving points and ego speed per scan")
    return save_figure(fig, data.dir, "fig_table2_dataset.png")


def figure_motion(data, min_accuracy):
    """Fig. 5: precision, recall and accuracy per frame."""
    fig, axes = plt.subplots(3, 1, figsize=(11, 7.5), sharex=True)
    for m in data.methods:
        f = data.frames[m]
        t = data.time_s(m)
        for ax, key in zip(axes, ["precision", "recall", "accuracy"]):
            ax.plot(t, f[key], method_style(m), color=method_colour(m, data.methods), lw=1.5, label=m)
    for ax, key in zip(axes, ["Precision (Eq. 23)", "Recall (Eq. 24)", "Accuracy (Eq. 25)"]):
        ax.set_ylabel(key.split(" ")[0])
        ax.set_title(key, loc="left", fontsize=10)
        lo = np.nanmin([np.nanmin(data.frames[m][key.split(" ")[0].lower()]) for m in data.methods] + [0.95])
        ax.set_ylim(max(0.0, lo - 0.02), 1.005)
    axes[2].axhline(min_accuracy, color="k", ls=":", lw=1.2, label=f"target {min_accuracy}")
    axes[0].legend(loc="lower left", ncol=len(data.methods))
    axes[2].legend(loc="lower left", ncol=len(data.methods) + 1)
    axes[2].set_xlabel("time [s]")
    fig.suptitle(f"Moving/static classification per frame, '{data.metrics['scenario']}' (Fig. 5){_legend_note(data)}",
                 fontsize=11)
    fig.tight_layout()
    return save_figure(fig, data.dir, "fig5_motion_per_frame.png")


def figure_time(data):
    """Fig. 6: time per frame, clustering and the whole pipeline."""
    fig, axes = plt.subplots(1, 2, figsize=(12, 3.8))
    for m in data.methods:
        f = data.frames[m]
        t = data.time_s(m)
        c = method_colour(m, data.methods)
        axes[0].plot(t, f["clustering_ms"], method_style(m), color=c, lw=1.3,
                     label=f"{m} (mean {np.mean(f['clustering_ms']):.2f} ms)")
        axes[1].plot(t, f["total_ms"], method_style(m), color=c, lw=1.3,
                     label=f"{m} (mean {np.mean(f['total_ms']):.2f} ms)")
    axes[0].set_title("Clustering (Algorithm 1)")
    axes[1].set_title("Whole pipeline: clustering + ego + objects")
    for ax in axes:
        ax.set_xlabel("time [s]")
        ax.set_ylabel("time per frame [ms]")
        ax.set_ylim(bottom=0)
        ax.legend(loc="upper right")
    fig.suptitle("Processing time per frame (Fig. 6; the paper: under 20 ms for clustering on a Ryzen 3600X)",
                 fontsize=11)
    fig.tight_layout()
    return save_figure(fig, data.dir, "fig6_time_per_frame.png")


def figure_ego(data, limits):
    """Fig. 7: ego velocity error per axis over time."""
    fig, axes = plt.subplots(3, 1, figsize=(11, 7.5), sharex=True)
    rotating = False
    for m in data.methods:
        f = data.frames[m]
        t = data.time_s(m)
        c = method_colour(m, data.methods)
        for k, (ax, axis) in enumerate(zip(axes, "xyz")):
            ax.plot(t, f[f"err_{axis}_mps"], method_style(m), color=c, lw=1.4, label=f"{m}")
            heads = f[f"err_heads_{axis}_mps"]
            if m == data.default and np.nanmax(np.abs(heads - f[f"err_{axis}_mps"])) > 1e-3:
                rotating = True
                ax.plot(t, heads, ":", color="k", lw=1.2, label=f"{m}, against the velocity of the mean head mount")
    for ax, axis, lim in zip(axes, "xyz", limits):
        ax.axhspan(-lim, lim, color="#2ca02c", alpha=0.12, label=f"target ±{lim} m/s")
        ax.set_ylabel(f"error {axis} [m/s]")
        vals = np.concatenate([data.frames[m][f"err_{axis}_mps"] for m in data.methods])
        vals = vals[np.isfinite(vals)]
        span = max(2.5 * lim, np.abs(vals).max() * 1.1 if vals.size else lim)
        ax.set_ylim(-span, span)
    handles, labels = [], []
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels and not lab.startswith("target"):
                handles.append(h)
                labels.append(lab)
    handles.append(plt.Rectangle((0, 0), 1, 1, color="#2ca02c", alpha=0.12))
    labels.append("target band")
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), bbox_to_anchor=(0.5, 0.0))
    axes[2].set_xlabel("time [s]")
    note = "\ndotted: the same estimate against the heads' own velocity (the rig turns; heads sit ahead of its origin)" \
        if rotating else ""
    fig.suptitle(f"Ego velocity error (estimate − truth at the rig origin), '{data.metrics['scenario']}' (Fig. 7){note}",
                 fontsize=10.5)
    fig.tight_layout(rect=(0, 0.04, 1, 1))
    return save_figure(fig, data.dir, "fig7_ego_velocity_error.png")


def _binned_median(x, y, edges):
    centres, medians = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        sel = (x >= lo) & (x < hi) & np.isfinite(y)
        if sel.sum() >= 3:
            centres.append(np.sqrt(lo * hi))
            medians.append(np.median(y[sel]))
    return np.array(centres), np.array(medians)


def figure_objects(data, large_pixels, max_median):
    """Fig. 8: object velocity error against the number of points."""
    y_min, y_max = 1e-3, 1e2  # [m/s] plotted range; errors beyond it are drawn on the edge
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8), sharey=True)
    titles = ["vs mean true velocity of the cluster's points", "vs the actor's reference velocity (its origin)"]
    any_points = False
    for ax, key, title in zip(axes, ["err_mps", "ref_err_mps"], titles):
        clipped = {}
        for m in data.methods:
            o = data.objects[m]
            sel = (o["evaluated"] == 1) & (o["estimate_valid"] == 1)
            x, y = o["pixels"][sel], o[key][sel]
            if x.size == 0:
                continue
            any_points = True
            c = method_colour(m, data.methods)
            high = y > y_max
            clipped[m] = int(high.sum())
            ax.scatter(x[~high], np.maximum(y[~high], y_min), s=10, alpha=0.45, color=c, edgecolors="none",
                       label=f"{m} ({x.size} object-frames)")
            if high.any():
                ax.scatter(x[high], np.full(high.sum(), y_max), s=22, marker="^", color=c, edgecolors="k",
                           linewidths=0.4)
            edges = np.logspace(0, np.log10(max(x.max(), 10) * 1.01), 14)
            bx, by = _binned_median(x, y, edges)
            ax.plot(bx, by, method_style(m), color=c, lw=2.2, label=f"{m}: median per size bin")
        ax.axvline(large_pixels, color="k", ls=":", lw=1.2)
        ax.axhline(max_median, color="#2ca02c", ls="--", lw=1.3, label=f"target {max_median} m/s (≥ {large_pixels} pts)")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_ylim(y_min * 0.8, y_max * 1.6)
        ax.set_xlabel("points on the object (valid pixels)")
        ax.set_title(title, fontsize=10)
        ax.text(large_pixels * 1.08, 0.03, f"{large_pixels} points", transform=ax.get_xaxis_transform(), fontsize=8.5)
        if any(clipped.values()):
            note = ", ".join(f"{m}: {n}" for m, n in clipped.items() if n)
            ax.text(0.99, 0.99, f"▲ errors above {y_max:g} m/s ({note})", transform=ax.transAxes, ha="right",
                    va="top", fontsize=8.5)
    axes[0].set_ylabel("velocity error |estimate − truth| [m/s]")
    if any_points:
        axes[0].legend(loc="lower left", fontsize=8.5)
    fig.suptitle(f"Object velocity error vs object size, detected objects, '{data.metrics['scenario']}' (Fig. 8)",
                 fontsize=11)
    fig.tight_layout()
    return save_figure(fig, data.dir, "fig8_object_velocity_error.png")


def figure_velocity_time(data):
    """Fig. 9: velocity-estimation time (ego + objects) against the number of moving clusters."""
    fig, ax = plt.subplots(figsize=(8.5, 4.8))
    for m in data.methods:
        f = data.frames[m]
        x = f["clusters"]
        y = f["ego_ms"] + f["objects_ms"]
        c = method_colour(m, data.methods)
        ax.scatter(x, y, s=14, alpha=0.6, color=c, edgecolors="none")
        if np.unique(x).size >= 2:
            slope, intercept = np.polyfit(x, y, 1)
            xs = np.array([0, x.max()])
            ax.plot(xs, intercept + slope * xs, method_style(m), color=c, lw=2,
                    label=f"{m}: {intercept:.3f} ms + {slope * 1000:.1f} µs × clusters")
        else:
            ax.plot([], [], color=c, label=m)
    ax.set_xlabel("moving clusters in the frame")
    ax.set_ylabel("velocity estimation time [ms]\n(ego + all objects)")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.legend(loc="upper left")
    ax.set_title("Velocity-estimation time vs number of moving clusters (Fig. 9); intercept ≈ ego time", fontsize=10.5)
    fig.tight_layout()
    return save_figure(fig, data.dir, "fig9_velocity_time_vs_clusters.png")


def figure_error_cdf(data, large_pixels):
    """The tail: the CDF of the centre-velocity error per method, objects with ≥ large_pixels points."""
    fig, ax = plt.subplots(figsize=(8.5, 4.8))
    x_min = 1e-4  # [m/s] errors below it are drawn at it
    drawn = False
    for m in data.methods:
        o = data.objects[m]
        sel = (o["evaluated"] == 1) & (o["estimate_valid"] == 1) & (o["pixels"] >= large_pixels)
        e = np.sort(o["ref_err_mps"][sel])
        e = e[np.isfinite(e)]
        if e.size == 0:
            continue
        drawn = True
        share = np.arange(1, e.size + 1) / e.size
        ax.step(np.maximum(e, x_min), share, where="post", color=method_colour(m, data.methods), lw=1.8,
                ls=method_style(m), label=f"{m} ({e.size} object-frames)")
    for v, name in [(0.5, "0.5 m/s"), (1.0, "1 m/s")]:
        ax.axvline(v, color="k", ls=":", lw=1.0)
        ax.text(v * 1.05, 0.03, name, fontsize=8.5)
    ax.axhline(0.95, color="#2ca02c", ls="--", lw=1.0, label="95 %")
    ax.set_xscale("log")
    ax.set_ylim(0, 1.01)
    ax.set_xlabel("|estimate − velocity at the actor's centre| [m/s]")
    ax.set_ylabel("share of object-frames with a smaller error")
    ax.set_title(f"Error of the velocity at the object's centre, objects with ≥ {large_pixels} points: the tail",
                 fontsize=10.5)
    if drawn:
        ax.legend(loc="upper left", fontsize=8.5)
    fig.tight_layout()
    return save_figure(fig, data.dir, "fig_error_cdf.png")


def draw_all(data):
    """Every figure; returns {key: file name or None}."""
    t = data.metrics["targets"]
    return {
        "dataset": figure_dataset(data),
        "fig5": figure_motion(data, t["min_accuracy"]),
        "fig6": figure_time(data),
        "fig7": figure_ego(data, t["max_ego_rmse_mps"]),
        "fig8": figure_objects(data, t["large_object_pixels"], t["max_median_error_ge200_mps"]),
        "fig9": figure_velocity_time(data),
        "cdf": figure_error_cdf(data, t["large_object_pixels"]),
        "fig4": figure_range_image(data),
        "fig1": figure_bev(data),
    }
