"""`fmcw study threshold` and `fmcw study object-points`: parameter sweeps on a dataset or scenario."""

import os

import matplotlib.pyplot as plt
import numpy as np

from report_common import (esc, fmt, html_figure, html_page, html_table, method_colour, read_table, save_figure,
                           select)


def threshold(out_dir, metrics):
    t = read_table(os.path.join(out_dir, metrics["files"]["sweep"]))
    order = np.argsort(t["threshold_mps"])
    t = select(t, order)
    paper, bound = metrics["paper_threshold_mps"], metrics["eq14_bound_mps"]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    ax = axes[0]
    for key, c in [("precision", "#1f77b4"), ("recall", "#ff7f0e"), ("accuracy", "#2ca02c")]:
        ax.plot(t["threshold_mps"], t[key], "o-", color=c, label=key, ms=4)
    ax.axvline(paper, color="k", ls="--", lw=1, label=f"paper: {paper} m/s")
    ax.set_xscale("log")
    ax.set_xlabel("Doppler threshold v_th [m/s]")
    ax.set_ylabel("pooled over all frames")
    ax.set_title("Moving/static classification against v_th")
    ax.legend(loc="lower left")
    ax = axes[1]
    ax.plot(t["recall"], t["precision"], "-", color="#7f7f7f", lw=1)
    sc = ax.scatter(t["recall"], t["precision"], c=np.log10(t["threshold_mps"]), cmap="viridis", s=40, zorder=3)
    last = None
    for x, y, v in zip(t["recall"], t["precision"], t["threshold_mps"]):
        if last is None or np.hypot(x - last[0], (y - last[1]) * 2) > 0.06 or v == paper:
            ax.annotate(f"{v:g}", (x, y), textcoords="offset points", xytext=(4, 5), fontsize=8)
            last = (x, y)
    k = np.argmin(np.abs(t["threshold_mps"] - paper))
    ax.scatter([t["recall"][k]], [t["precision"][k]], s=160, facecolors="none", edgecolors="r", lw=1.5,
               label=f"v_th = {t['threshold_mps'][k]:g} m/s (paper)")
    cb = fig.colorbar(sc, ax=ax)
    cb.set_label("log10 v_th [m/s]")
    ax.set_xlabel("recall")
    ax.set_ylabel("precision")
    ax.set_title("Precision/recall trade-off (labels: v_th in m/s)")
    ax.legend(loc="lower left")
    ax = axes[2]
    for k2, (axis, c) in enumerate(zip("xyz", ["#1f77b4", "#ff7f0e", "#2ca02c"])):
        ax.plot(t["threshold_mps"], t[f"ego_rmse_{axis}_mps"], "o-", ms=3.5, color=c, label=f"ego RMSE {axis}")
    ax.plot(t["threshold_mps"], t["median_error_mps_ge200"], "s--", ms=4, color="k",
            label="median object error (≥ 200 pts)")
    ax.axvline(paper, color="k", ls="--", lw=1)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("Doppler threshold v_th [m/s]")
    ax.set_ylabel("velocity error [m/s]")
    ax.set_title("Velocity errors downstream of the labels")
    ax.legend(loc="best", fontsize=8)
    fig.suptitle(f"Doppler threshold sweep on '{metrics['scenario']}' ({metrics['frames_used']} frames, method "
                 f"'{metrics['method']}'); Eq. 14 bound for 25 m/s: {bound:.4f} m/s", fontsize=11)
    fig.tight_layout()
    figures = {"sweep": save_figure(fig, out_dir, "threshold_sweep.png")}

    best = int(np.nanargmax(t["accuracy"]))
    rows = [[f"{v:g}", fmt(p_, 4), fmt(r_, 4), fmt(a_, 5), f"{c_:.1f}", " / ".join(fmt(x, 2) for x in e),
             fmt(m_, 3)]
            for v, p_, r_, a_, c_, e, m_ in zip(t["threshold_mps"], t["precision"], t["recall"], t["accuracy"],
                                                t["mean_clusters"],
                                                zip(t["ego_rmse_x_mps"], t["ego_rmse_y_mps"], t["ego_rmse_z_mps"]),
                                                t["median_error_mps_ge200"])]
    classes = [[None] * 7 for _ in rows]
    classes[best][3] = "pass"
    k = int(np.argmin(np.abs(t["threshold_mps"] - paper)))
    body = [f"<h1>Doppler threshold v_th: precision/recall trade-off on '{esc(metrics['scenario'])}'</h1>",
            f"<p class=\"small\">Source <code>{esc(metrics['source'])}</code>, {metrics['frames_used']} frames "
            f"(every {metrics['stride']}.), method <code>{esc(metrics['method'])}</code> (every method grows the "
            f"same regions); {metrics['seconds']:.1f} s.</p>",
            f"<p>At the paper's v_th = {paper} m/s: precision {fmt(t['precision'][k], 4)}, recall "
            f"{fmt(t['recall'][k], 4)}, accuracy {fmt(t['accuracy'][k], 5)}. The highest accuracy in this sweep is "
            f"{fmt(t['accuracy'][best], 5)} at v_th = {t['threshold_mps'][best]:g} m/s. Lower thresholds split "
            "objects and the static world into more regions (more clusters, lower precision); higher thresholds "
            "merge slow or crossing objects into the static region (lower recall). Eq. 14 bounds the Doppler step "
            f"inside one rigid object at 25 m/s by {bound:.4f} m/s.</p>",
            html_table(["v_th [m/s]", "precision", "recall", "accuracy", "clusters/frame", "ego RMSE x / y / z [m/s]",
                        "median object error ≥ 200 pts [m/s]"], rows, classes=classes),
            html_figure(figures["sweep"], "Left: precision, recall and accuracy against v_th. Middle: the "
                                          "precision/recall curve. Right: ego and object velocity errors.")]
    return html_page("Threshold study", "\n".join(body)), figures


def object_points(out_dir, metrics):
    t = read_table(os.path.join(out_dir, metrics["files"]["sweep"]))
    solvers = list(dict.fromkeys(t["solver"]))
    paper_cap = metrics["paper_cap"]
    all_cap = max(float(np.max(t["cap"])) * 2, 4000.0)  # where "every point" (cap 0) is drawn
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.8))
    colours = {"ceres": method_colour("paper", []), "closed_form": method_colour("fast", [])}
    summary = {}
    for s in solvers:
        sel = t["solver"] == s
        caps = np.where(t["cap"][sel] == 0, all_cap, t["cap"][sel])
        order = np.argsort(caps)
        caps = caps[order]
        err = t["median_error_mps_ge200"][sel][order]
        sub = t["median_subsample_error_mps_ge200"][sel][order]
        ms = t["mean_objects_ms"][sel][order]
        c = colours.get(s, "#2ca02c")
        style = "-" if s == solvers[0] else "--"
        axes[0].plot(caps, err, "o" + style, color=c, label=f"{s}: median error vs truth")
        shown = sub > 0
        axes[0].plot(caps[shown], sub[shown], "s" + style, color=c, mfc="white",
                     label=f"{s}: median |V(cap) − V(all)| (subsampling alone)")
        axes[1].plot(caps, ms, "o-", color=c, label=s)
        summary[s] = (caps, err, ms, sub)
    for ax in axes:
        ax.axvline(paper_cap, color="k", ls="--", lw=1)
        ax.set_xscale("log")
        ticks = sorted(set(np.where(t["cap"] == 0, all_cap, t["cap"])))
        ax.set_xticks(ticks)
        ax.set_xticklabels(["all" if x == all_cap else f"{int(x)}" for x in ticks], rotation=45)
        ax.set_xlabel("num_th^m: points per cluster (random subset)")
    axes[0].set_yscale("log")
    axes[0].axhline(0.1, color="#2ca02c", ls=":", lw=1.2, label="0.1 m/s (paper's accuracy)")
    axes[0].set_ylabel("object velocity error [m/s]\n(objects with ≥ 200 points)")
    axes[0].set_title("Accuracy against num_th^m (dashed: the paper's 200)")
    axes[0].legend(fontsize=8, loc="lower left")
    axes[1].set_yscale("log")
    axes[1].set_ylabel("object-estimation time per frame [ms]")
    axes[1].set_title("Time against num_th^m")
    axes[1].legend(fontsize=8)
    fig.suptitle(f"Points per object (Algorithm 2), '{metrics['scenario']}', {metrics['frames_used']} frames",
                 fontsize=11)
    fig.tight_layout()
    figures = {"sweep": save_figure(fig, out_dir, "object_points_sweep.png")}

    verdicts = []
    for s, (caps, err, ms, sub) in summary.items():
        full = err[-1]
        at = np.where(caps == paper_cap)[0]
        within = caps[np.where(err <= full * 1.1)[0][0]] if np.isfinite(full) else np.nan
        if at.size:
            k = at[0]
            verdicts.append(
                f"<li><code>{esc(s)}</code>: at 200 points the median error is {fmt(err[k], 3)} m/s against "
                f"{fmt(full, 3)} m/s with every point ({(err[k] / full - 1) * 100:+.0f} %), for "
                f"{fmt(ms[k], 3)} ms against {fmt(ms[-1], 3)} ms per frame. Subsampling alone moves the estimate "
                f"by a median {fmt(sub[k], 3)} m/s at 200 points. The smallest cap within 10 % of the all-points "
                f"error is {'all' if within == all_cap else fmt(int(within))}.</li>")
    rows = [[esc(s), "all" if c == 0 else f"{int(c)}", fmt(int(n)), fmt(m, 3), fmt(sb, 3), fmt(p, 3), fmt(ms_, 3),
             fmt(pc * 1000, 3)]
            for s, c, n, m, sb, p, ms_, pc in zip(t["solver"], t["cap"], t["objects_large"],
                                                 t["median_error_mps_ge200"], t["median_subsample_error_mps_ge200"],
                                                 t["p90_error_mps_ge200"], t["mean_objects_ms"],
                                                 t["objects_ms_per_cluster"])]
    body = [f"<h1>Points per object num_th^m: accuracy against time on '{esc(metrics['scenario'])}'</h1>",
            f"<p class=\"small\">Source <code>{esc(metrics['source'])}</code>, {metrics['frames_used']} frames; the "
            "<code>paper</code> method (region growing, ego from 1000 random static points) with each cluster "
            "estimated on a random subset of at most num_th^m points, by Ceres (Algorithm 2) or by the closed "
            f"form; {metrics['num_threads']} thread(s) for objects; {metrics['seconds']:.1f} s. Errors against the "
            "mean true velocity of each detected object's points; objects with at least "
            f"{metrics['large_object_pixels']} points.</p>",
            "<h2>Does the paper's 200 hold?</h2><ul>" + "".join(verdicts) + "</ul>",
            html_table(["solver", "num_th^m", "object-frames ≥ 200 pts", "median error vs truth [m/s]",
                        "median |V(cap) − V(all)| [m/s]", "90th percentile vs truth [m/s]",
                        "objects time [ms/frame]", "per cluster [µs]"], rows),
            "<p class=\"small\">The error against the truth includes what no cap can fix (turning actors, limbs and "
            "wheels, lateral motion a small patch cannot observe); |V(cap) − V(all)| isolates what the random "
            "subset costs. Ceres and the closed form solve the same least-squares problem on the same subset, so "
            "their errors coincide; only the time differs.</p>",
            html_figure(figures["sweep"], "Left: median object velocity error against the cap (filled) and the "
                                          "part due to subsampling alone (hollow); right: time of the object "
                                          "stage per frame.")]
    return html_page("Object-points study", "\n".join(body)), figures
