"""report.html of an aggregate evaluation (`fmcw evaluate FOLDER`, a folder of datasets): pooled
metrics with their spread across scenarios, the share of scenarios meeting each target, one
row per scenario, and the metrics against layout, speed and density. Every number shown is in
metrics.json or a table beside it; nothing is computed here but positions on the page."""

import os

import matplotlib.pyplot as plt
import numpy as np

from evaluation_html import TARGET_TEXT
from report_common import (esc, fmt, html_figure, html_page, html_table, method_colour, read_table, save_figure,
                           select)

# (column of scenarios.csv, axis label, log scale): the panels of each figure.
PANELS = [
    ("accuracy", "motion accuracy (Eq. 25)", False),
    ("centre_err_median_ge200_mps", "centre-velocity error, median,\n≥ 200 points [m/s]", True),
    ("centre_err_p95_ge200_mps", "centre-velocity error, p95,\n≥ 200 points [m/s]", True),
    ("ego_rmse_y_mps", "ego velocity RMSE y [m/s]", True),
    ("detected_fraction", "detected fraction", False),
    ("band_recall", "blind-band recall", False),
]


def _positive(values):
    """Log axes cannot show 0: errors of exactly 0 are drawn at the axis floor."""
    v = np.array(values, dtype=float)
    finite = v[np.isfinite(v) & (v > 0)]
    floor = finite.min() / 2 if finite.size else 1e-3
    return np.where(np.isfinite(v) & (v <= 0), floor, v)


def _axis_values(table, column):
    return table[column] if column in table else None


def _figure(out_dir, metrics, table, axis_key, name):
    axis = metrics["axes"][axis_key]
    column = axis["column"]
    methods = metrics["method_order"]
    x_all = _axis_values(table, column)
    if x_all is None:
        return None
    categorical = x_all.dtype == object
    if categorical:
        categories = sorted({str(c) for c in x_all if str(c) != ""})
        if not categories:
            return None
    elif not np.any(np.isfinite(x_all)):
        return None
    fig, axes = plt.subplots(2, 3, figsize=(15, 8.2))
    width = 0.8 / max(1, len(methods))
    for ax, (key, label, log) in zip(axes.flat, PANELS):
        if not np.any(np.isfinite(table[key])):
            ax.text(0.5, 0.5, "nothing measured in any scenario", ha="center", va="center", transform=ax.transAxes,
                    color="#555")
            ax.set_ylabel(label)
            continue
        for k, m in enumerate(methods):
            t = select(table, table["method"] == m)
            y = t[key] if not log else _positive(t[key])
            colour = method_colour(m, methods)
            if categorical:
                pos = {c: i for i, c in enumerate(categories)}
                keep = np.array([str(c) in pos for c in t[column]], dtype=bool)
                xs = np.array([pos[str(c)] for c in t[column][keep]], dtype=float) - 0.4 + width * (k + 0.5)
                ax.scatter(xs, y[keep], s=22, color=colour, alpha=0.8, label=m, zorder=3)
                # The median of each category, from the scenarios' own values.
                for c, i in pos.items():
                    yc = y[keep][np.array([str(v) == c for v in t[column][keep]], dtype=bool)]
                    yc = yc[np.isfinite(yc)]
                    if yc.size:
                        x0 = i - 0.4 + width * k
                        ax.plot([x0, x0 + width], [np.median(yc)] * 2, color=colour, lw=2)
            else:
                ax.scatter(t[column], y, s=22, color=colour, alpha=0.8, label=m, zorder=3)
        if categorical:
            ax.set_xticks(range(len(categories)))
            ax.set_xticklabels(categories, rotation=30, ha="right", fontsize=8)
        else:
            ax.set_xlabel(f"{column}")
        if log:
            ax.set_yscale("log")
        ax.set_ylabel(label)
    axes.flat[0].legend(loc="best", fontsize=8)
    source = "the scenario manifest" if axis["source"] == "manifest" else "the datasets (no manifest column)"
    fig.suptitle(f"Per-scenario metrics against {axis['meaning']} (column '{column}', from {source}); "
                 "one point per scenario and method" + ("; bars: medians per category" if categorical else ""),
                 fontsize=11)
    fig.tight_layout()
    return save_figure(fig, out_dir, name)


def _targets_figure(out_dir, metrics, targets):
    methods = metrics["method_order"]
    keys = metrics["target_keys"] + ["all"]
    fig, ax = plt.subplots(figsize=(12, 4.6))
    width = 0.8 / max(1, len(methods))
    for k, m in enumerate(methods):
        t = select(targets, targets["method"] == m)
        share = {str(key): s for key, s in zip(t["target"], t["share_met"])}
        ys = [share.get(key, np.nan) for key in keys]
        ax.bar(np.arange(len(keys)) - 0.4 + width * (k + 0.5), np.nan_to_num(ys), width, label=m,
               color=method_colour(m, methods))
    ax.set_xticks(range(len(keys)))
    ax.set_xticklabels(keys, rotation=25, ha="right", fontsize=8)
    ax.set_ylim(0, 1.05)
    ax.set_ylabel("share of scenarios meeting the target")
    ax.set_title("Targets met across scenarios (a target is held only where it can be measured: the blind band)")
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, out_dir, "fig_targets_met.png")


def _pooled_rows(metrics):
    methods = metrics["method_order"]
    pooled = metrics["pooled"]
    large = metrics["targets"]["large_object_pixels"]

    def get(path):
        out = []
        for m in methods:
            v = pooled[m]
            for p in path.split("."):
                v = v[p]
            out.append(v)
        return out

    def spread(key, digits):
        cells = []
        for m in methods:
            s = pooled[m]["spread"][key]
            cells.append(f"{fmt(s['median'], digits)} [{fmt(s['p10'], digits)}, {fmt(s['p90'], digits)}]")
        return cells

    rows = [
        ["scenarios / frames"] + [f"{a} / {b}" for a, b in zip(get("scenarios"), get("frames"))],
        ["frames not ok"] + [fmt(v) for v in get("frames_not_ok")],
        ["accuracy, pooled"] + [fmt(v, 5) for v in get("motion.accuracy")],
        ["accuracy, median [p10, p90] of scenarios"] + spread("accuracy", 4),
        ["precision / recall, pooled"] + [f"{fmt(p, 4)} / {fmt(r, 4)}" for p, r in
                                          zip(get("motion.precision"), get("motion.recall"))],
        ["ego RMSE x / y / z, pooled [m/s]"] + [" / ".join(fmt(x, 2) for x in v)
                                                for v in get("ego_velocity.rmse_mps")],
        ["ego yaw-rate RMSE, pooled [°/s]"] + [fmt(v, 3) for v in get("ego_velocity.yaw_rate_rmse_dps")],
        ["detected fraction, pooled"] + [fmt(v, 4) for v in get("objects.detected_fraction")],
    ]
    for label, key in [(f"≥ {large} points", "centre_error_mps_ge200"), ("all estimated", "centre_error_mps")]:
        rows.append([f"centre-velocity error, {label}: median / p95 / max [m/s] (object-frames)"] +
                    [f"{fmt(e['median'], 3)} / {fmt(e['p95'], 3)} / {fmt(e['max'], 3)} ({e['count']})"
                     for e in get(f"objects.{key}")])
        rows.append([f"share of estimates off by > 1 m/s, {label}"] +
                    [fmt(e["share_over_1mps"], 3) for e in get(f"objects.{key}")])
    rows.append([f"centre median ≥ {large} points, median [p10, p90] of scenarios [m/s]"] +
                spread("centre_err_median_ge200_mps", 3))
    rows.append(["blind-band recall, pooled (band pixels)"] +
                [f"{fmt(b['recall_tracked'], 3)} ({b['band_pixels']})" for b in get("blind_zone")])
    rows.append(["instance precision / recall, pooled"] +
                [f"{fmt(p, 3)} / {fmt(r, 3)}" for p, r in
                 zip(get("objects.instance_precision"), get("objects.instance_recall"))])
    rows.append(["time per frame, mean [ms]"] + [fmt(v, 3) for v in get("timing_ms.total")])
    return rows


def _target_rows(metrics):
    methods = metrics["method_order"]
    pooled = metrics["pooled"]
    rows, classes = [], []
    for i, key in enumerate(metrics["target_keys"]):
        row = [esc(TARGET_TEXT.get(key, key))]
        cls = [None]
        t0 = pooled[methods[0]]["targets"][i]
        for m in methods:
            t = pooled[m]["targets"][i]
            row.append(f"{t['scenarios_met']} of {t['scenarios_checked']} ({fmt(t['share_met'], 3)})"
                       if t["scenarios_checked"] else "not held")
            cls.append("pass" if t["scenarios_checked"] and t["scenarios_met"] == t["scenarios_checked"] else
                       ("fail" if t["scenarios_checked"] else None))
        row.append(esc(f"{t0['relation']} {t0['limit']:g}"))
        cls.append(None)
        rows.append(row)
        classes.append(cls)
    row = ["every target held"]
    for m in methods:
        a = pooled[m]["all_targets_met"]
        row.append(f"{a['scenarios_met']} of {pooled[m]['scenarios']} ({fmt(a['share_met'], 3)})")
    rows.append(row + [""])
    classes.append([None] * len(row) + [None])
    return rows, classes


def _scenario_rows(metrics):
    methods = metrics["method_order"]
    rows, classes = [], []
    for s in metrics["scenarios"]:
        row = [esc(s["dataset"]), esc(s["scenario"]), fmt(s["frames"])]
        cls = [None, None, None]
        for m in methods:
            x = s["methods"][m]
            missed = [k for k, met in x["targets"].items() if not met]
            row += [fmt(x["accuracy"], 4), fmt(x["centre_err_median_ge200_mps"], 3),
                    "all met" if not missed else esc(", ".join(missed))]
            cls += [None, None, "pass" if not missed else "fail"]
        rows.append(row)
        classes.append(cls)
    return rows, classes


def report(out_dir, metrics):
    files = metrics["files"]
    table = read_table(os.path.join(out_dir, files["scenarios"]))
    targets = read_table(os.path.join(out_dir, files["targets"]))
    methods = metrics["method_order"]
    figures = {
        "layout": _figure(out_dir, metrics, table, "layout", "fig_metrics_vs_layout.png"),
        "speed": _figure(out_dir, metrics, table, "speed", "fig_metrics_vs_speed.png"),
        "density": _figure(out_dir, metrics, table, "density", "fig_metrics_vs_density.png"),
        "targets": _targets_figure(out_dir, metrics, targets),
    }
    default = metrics["default_method"]
    body = [f"<h1>Aggregate evaluation of {metrics['datasets']} datasets</h1>",
            f"<p class=\"small\">Folder <code>{esc(metrics['folder'])}</code>; methods "
            f"{', '.join('<code>' + esc(m) + '</code>' for m in methods)} (<code>paper</code> is the baseline, "
            f"<code>{esc(default)}</code> the default); "
            + (f"first {metrics['config']['max_frames']} frames of each dataset; " if metrics["config"]["max_frames"]
               else "every frame; ")
            + "tool " + esc(metrics["tool_version"]) + ". Each dataset's own metrics are in "
            "<code>datasets/&lt;folder&gt;/metrics.json</code>.</p>"]
    if metrics["failures"]:
        items = "".join(f"<li><code>{esc(f['dataset'])}</code>: {esc(f['error'])}</li>" for f in metrics["failures"])
        body.append(f"<div class=\"missed\"><b>Incomplete: {len(metrics['failures'])} of {metrics['datasets']} "
                    f"datasets failed to evaluate</b> and are not in any number below:<ul>{items}</ul></div>")
    for note in metrics["notes"]:
        body.append(f"<p class=\"small\">Note: {esc(note)}</p>")
    header = ["metric"] + [esc(m) for m in methods]
    body.append("<h2>Pooled over the scenarios</h2>")
    body.append("<p>Pooled: confusion counts summed over every frame of every scenario; ego RMSEs from the summed "
                "squared errors; object errors over every estimated object-frame of every scenario. "
                "[p10, p90]: the spread of the per-scenario values (<code>spread.csv</code>).</p>")
    body.append(html_table(header, _pooled_rows(metrics)))
    body.append("<h2>Share of scenarios meeting each target</h2>")
    rows, classes = _target_rows(metrics)
    body.append(html_table(["target"] + [esc(m) for m in methods] + ["target"], rows, classes=classes))
    misses = [(s["dataset"], [k for k, met in s["methods"][default]["targets"].items() if not met])
              for s in metrics["scenarios"] if default in s["methods"]]
    misses = [(d, k) for d, k in misses if k]
    if misses:
        items = "".join(f"<li><code>{esc(d)}</code>: {esc(', '.join(k))}</li>" for d, k in misses)
        body.append(f"<div class=\"missed\"><b>Where <code>{esc(default)}</code> misses</b> "
                    f"({len(misses)} of {len(metrics['scenarios'])} scenarios); each scenario's "
                    f"<code>datasets/&lt;folder&gt;/metrics.json</code> has the numbers:<ul>{items}</ul></div>")
    else:
        body.append(f"<div class=\"ok\"><code>{esc(default)}</code> meets every target on every scenario.</div>")
    body.append("<h2>Per scenario</h2>")
    sub = []
    for m in methods:
        sub += [f"{esc(m)}: accuracy", f"{esc(m)}: centre median ≥ 200 pts [m/s]", f"{esc(m)}: targets missed"]
    rows, classes = _scenario_rows(metrics)
    body.append(html_table(["dataset", "scenario", "frames"] + sub, rows, name_columns=2, classes=classes))
    body.append("<p class=\"small\">Every column, and the manifest's, is in <code>scenarios.csv</code>.</p>")
    body.append("<h2>Against layout, speed and density</h2>")
    captions = {
        "layout": "Per-scenario metrics by layout",
        "speed": "Per-scenario metrics against speed",
        "density": "Per-scenario metrics against traffic density",
        "targets": "Share of scenarios meeting each target, per method",
    }
    for key, name in figures.items():
        if name:
            axis = metrics["axes"].get(key)
            extra = ""
            if axis:
                extra = (f" (column <code>{esc(axis['column'])}</code>, from "
                         f"{'the manifest' if axis['source'] == 'manifest' else 'the datasets: no manifest column'})")
            body.append(html_figure(name, captions[key] + extra + "."))
        else:
            body.append(f"<p class=\"small\">No figure against {esc(key)}: no scenario has a value.</p>")
    return html_page("fmcw aggregate evaluation", "\n".join(body)), figures
