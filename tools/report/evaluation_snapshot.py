"""The snapshot frame's figures: the range image by |Doppler| (Fig. 4) and the bird's-eye view (Fig. 1)."""

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import ListedColormap
from matplotlib.patches import Patch

from report_common import save_figure, select


def _image(data, column):
    p = data.pixels
    rows = int(p["row"].max()) + 1
    cols = int(p["col"].max()) + 1
    return p[column].reshape(rows, cols)


def figure_range_image(data):
    """Fig. 4: range image coloured by absolute Doppler, and the default method's errors."""
    p = data.pixels
    if p["_rows"] == 0:
        return None
    valid = _image(data, "valid") == 1
    v = np.where(valid, np.abs(_image(data, "v_mps")), np.nan)
    rows, cols = v.shape
    width_in = 13.0
    img_h = 0.86 * width_in * rows / cols  # height of one image at the figure's width [in]
    fig = plt.figure(figsize=(width_in, 2 * img_h + 2.6))
    h = fig.get_figheight()
    ax_top = fig.add_axes([0.05, (img_h + 1.75) / h, 0.86, img_h / h])
    ax_bar = fig.add_axes([0.925, (img_h + 1.75) / h, 0.012, img_h / h])
    ax_bot = fig.add_axes([0.05, 0.95 / h, 0.86, img_h / h])
    cmap = plt.get_cmap("inferno").copy()
    cmap.set_bad("black")
    vmax = max(1.0, np.nanpercentile(v, 99.5))
    im = ax_top.imshow(v, cmap=cmap, vmin=0, vmax=vmax, interpolation="nearest", aspect="auto")
    cb = fig.colorbar(im, cax=ax_bar)
    cb.set_label("|Doppler| [m/s]")
    frame = data.metrics["snapshot_frame"]
    ax_top.set_title(f"Absolute Doppler velocity, frame {frame} (t = {frame / data.rate_hz:.1f} s); black: no return "
                     "or |v| ≈ 0 (Fig. 4)")

    m = data.default
    label = _image(data, f"label_{m}")
    moving_truth = _image(data, "moving") == 1
    predicted = (label >= 1) | (label == -2)
    classes = np.zeros(label.shape, dtype=int)  # 0 no return
    classes[valid & ~moving_truth & ~predicted] = 1  # TN
    classes[valid & moving_truth & predicted] = 2  # TP
    classes[valid & ~moving_truth & predicted] = 3  # FP
    classes[valid & moving_truth & ~predicted] = 4  # FN
    colours = ["black", "#cfcfcf", "#2ca02c", "#d62728", "#1f77b4"]
    ax_bot.imshow(classes, cmap=ListedColormap(colours), vmin=-0.5, vmax=4.5, interpolation="nearest", aspect="auto")
    counts = [(classes == k).sum() for k in range(5)]
    names = ["no return", "static, labelled static (TN)", "moving, labelled moving (TP)",
             "static, labelled moving (FP)", "moving, labelled static (FN)"]
    ax_bot.legend(handles=[Patch(color=c, label=f"{n}: {k:,}") for c, n, k in zip(colours, names, counts)],
                  loc="upper left", bbox_to_anchor=(1.005, 1.0), fontsize=8.5, frameon=False)
    ax_bot.set_title(f"Labels of '{m}' against the ground truth")
    for ax in (ax_top, ax_bot):
        ax.set_xlabel("column (azimuth, 0.2° per pixel, left to right)")
        ax.set_ylabel("row (elevation)")
        ax.grid(False)
        for c in _head_seams(cols):
            ax.axvline(c - 0.5, color="white", lw=0.6, alpha=0.6)
    return save_figure(fig, data.dir, "fig4_range_image_doppler.png")


def _head_seams(cols):
    # The paper rig: three heads of 200 columns; other rigs: no seam lines.
    return [200, 400] if cols == 600 else []


def _bev_limits(data, valid):
    """A view around everything that moves, and the static world near it [m]."""
    a, cl = data.actors, data.clusters
    xs = [0.0] + list(a["x_m"][a["pixels"] > 0]) + list(cl["centroid_x_m"][cl["pixels"] >= 20])
    ys = [0.0] + list(a["y_m"][a["pixels"] > 0]) + list(cl["centroid_y_m"][cl["pixels"] >= 20])
    x_lo, x_hi = min(xs) - 8.0, max(xs) + 10.0
    y_lo, y_hi = min(ys) - 8.0, max(ys) + 8.0
    px, py = data.pixels["x_m"][valid], data.pixels["y_m"][valid]
    x_hi = min(max(x_hi, np.percentile(px, 60)), np.percentile(px, 99.5) + 2.0)
    y_lo = max(min(y_lo, -15.0), np.percentile(py, 0.5) - 2.0)
    y_hi = min(max(y_hi, 15.0), np.percentile(py, 99.5) + 2.0)
    return (max(x_lo, -5.0), x_hi), (y_lo, y_hi)


def _draw_boxes(ax, a, seen):
    """The ground-truth boxes of the actors seen, from above: their outline, a tick at the front."""
    if "box_yaw_rad" not in a:  # a report of a dataset written before boxes
        return
    for k in np.flatnonzero(seen):
        c, s = np.cos(a["box_yaw_rad"][k]), np.sin(a["box_yaw_rad"][k])
        hl, hw = 0.5 * a["box_length_m"][k], 0.5 * a["box_width_m"][k]
        corners = [(hl, hw), (-hl, hw), (-hl, -hw), (hl, -hw), (hl, hw)]
        xs = [a["box_x_m"][k] + c * u - s * v for u, v in corners]
        ys = [a["box_y_m"][k] + s * u + c * v for u, v in corners]
        ax.plot(xs, ys, color="k", lw=0.8, alpha=0.8, zorder=3)
        ax.plot([a["box_x_m"][k], a["box_x_m"][k] + c * hl], [a["box_y_m"][k], a["box_y_m"][k] + s * hl], color="k",
                lw=0.8, alpha=0.8, zorder=3)


def figure_bev(data):
    """Fig. 1: bird's-eye view; static grey, each moving cluster its own colour, velocity arrows."""
    p = data.pixels
    if p["_rows"] == 0:
        return None
    valid = p["valid"] == 1
    x, y = p["x_m"], p["y_m"]
    (x_lo, x_hi), (y_lo, y_hi) = _bev_limits(data, valid)
    methods = data.methods
    ratio = (y_hi - y_lo) / (x_hi - x_lo)
    # Wide views stack the methods; square ones sit side by side.
    stacked = ratio < 0.6
    cols = 1 if stacked else min(2, len(methods))
    rows = -(-len(methods) // cols)
    panel_w = 13.0 if stacked else 6.6
    panel_h = (panel_w - 1.0) * ratio + 0.7
    fig, axes = plt.subplots(rows, cols, figsize=(panel_w * cols, panel_h * rows + 1.3), squeeze=False)
    axes = axes.ravel()
    for ax in axes[len(methods):]:
        ax.set_visible(False)
    # tab20 without its two greys (grey means static here).
    palette = [c for k, c in enumerate(plt.get_cmap("tab20").colors) if k not in (14, 15)]
    colour_of = lambda k: palette[(int(k) * 7) % len(palette)]  # noqa: E731  (spread neighbouring ids apart)
    a = data.actors
    for ax, m in zip(axes, methods):
        label = p[f"label_{m}"]
        static = valid & (label == 0)
        ax.scatter(x[static], y[static], s=0.8, color="#bdbdbd", edgecolors="none", rasterized=True)
        unassigned = valid & (label == -2)
        if unassigned.any():
            ax.scatter(x[unassigned], y[unassigned], s=2.0, color="k", edgecolors="none", rasterized=True)
        cl = select(data.clusters, data.clusters["method"] == m)
        moving = valid & (label >= 1)
        ax.scatter(x[moving], y[moving], s=5, c=[colour_of(k) for k in label[moving]], edgecolors="none",
                   rasterized=True)
        big = cl["pixels"] >= 20
        ok = big & (cl["valid"] == 1)
        seen = a["pixels"] > 0
        _draw_boxes(ax, a, seen)
        ax.quiver(a["x_m"][seen], a["y_m"][seen], a["vx_mps"][seen], a["vy_mps"][seen], angles="xy",
                  scale_units="xy", scale=1.0, width=0.0035 * (0.5 if stacked else 1.0), color="k", zorder=4)
        ax.quiver(cl["centroid_x_m"][ok], cl["centroid_y_m"][ok], cl["vx_mps"][ok], cl["vy_mps"][ok], angles="xy",
                  scale_units="xy", scale=1.0, width=0.006 * (0.5 if stacked else 1.0),
                  color=[colour_of(k) for k in cl["cluster"][ok]], edgecolor="k", linewidth=0.5, zorder=5)
        ax.plot([0], [0], marker=(3, 0, -90), ms=11, color="#d62728", ls="none", zorder=6)
        ax.set_xlim(x_lo, x_hi)
        ax.set_ylim(y_lo, y_hi)
        ax.set_aspect("equal")
        ax.set_xlabel("x forward [m]")
        ax.set_ylabel("y left [m]")
        ax.set_title(f"'{m}': {len(cl['cluster'])} moving clusters, {int(big.sum())} with ≥ 20 points", fontsize=10)
    handles = [plt.Line2D([], [], marker="o", ls="none", color="#bdbdbd", ms=6, label="static (label 0)"),
               plt.Line2D([], [], marker="o", ls="none", color=palette[2], ms=6, label="points of a moving cluster"),
               plt.Line2D([], [], color=palette[2], lw=3, label="its estimated velocity (clusters ≥ 20 points)"),
               plt.Line2D([], [], color="k", lw=1.2, label="true actor velocity (arrow = 1 s of motion)"),
               plt.Line2D([], [], color="k", lw=0.8, label="true box (a tick at its front)"),
               plt.Line2D([], [], marker=(3, 0, -90), ls="none", color="#d62728", ms=9, label="ego (rig origin)")]
    fig.legend(handles=handles, loc="lower center", ncol=6, fontsize=8.5, bbox_to_anchor=(0.5, 0.0))
    frame = data.metrics["snapshot_frame"]
    fig.suptitle(f"Bird's-eye view of frame {frame} (t = {frame / data.rate_hz:.1f} s), '{data.metrics['scenario']}': "
                 "static world grey, each moving cluster its own colour (Fig. 1)", fontsize=11)
    fig.tight_layout(rect=(0, 0.05 if not stacked else 0.03, 1, 0.98), h_pad=2.0)
    return save_figure(fig, data.dir, "fig1_birds_eye_view.png")
