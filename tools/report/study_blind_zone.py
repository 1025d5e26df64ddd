"""`fmcw study blind-zone`: recall against heading beside Eq. 15; figures and report.html."""

import os

import matplotlib.pyplot as plt
import numpy as np

from report_common import esc, fmt, html_figure, html_page, html_table, read_table, save_figure

TARGET_COLOURS = {10.0: "#d62728", 20.0: "#ff7f0e", 40.0: "#1f77b4"}


def _curve_label(target, distance):
    return f"{target.replace('_', ' ')} at {distance:g} m"


def _curve_colour(target, distance, k):
    if target == "car_box" or target == "mesh":
        return TARGET_COLOURS.get(distance, plt.get_cmap("tab10").colors[k % 10])
    return "k"


def _cases(samples):
    seen = []
    for t, d in zip(samples["target"], samples["distance_m"]):
        if (t, d) not in seen:
            seen.append((t, d))
    return seen


def _method_groups(samples, methods, noise_free):
    """Methods whose recall agrees at every sample, with and without noise, share one curve."""
    groups = []
    for m in methods:
        for g in groups:
            same = np.array_equal(samples[f"recall_{m}"], samples[f"recall_{g[0]}"])
            if noise_free:
                same = same and np.array_equal(samples[f"recall_noise_free_{m}"], samples[f"recall_noise_free_{g[0]}"])
            if same:
                g.append(m)
                break
        else:
            groups.append([m])
    return groups


def report(out_dir, metrics):
    samples = read_table(os.path.join(out_dir, metrics["files"]["samples"]))
    bands = read_table(os.path.join(out_dir, metrics["files"]["bands"]))
    p = metrics["params"]
    v_th = p["velocity_threshold_mps"]
    speeds = p["speeds_mps"]
    cases = _cases(samples)
    noise_free = p["noise_free_too"]
    groups = _method_groups(samples, metrics["methods"], noise_free)
    figures = {}
    for k, g in enumerate(groups):
        suffix = "" if k == 0 else f"_{g[0]}"
        figures[f"recall{suffix}"] = _blind_recall_figure(out_dir, samples, bands, speeds, cases, g, v_th, noise_free,
                                                          f"blind_zone_recall{suffix}.png")
        figures[f"edges{suffix}"] = _blind_edges_figure(out_dir, bands, speeds, cases, g, v_th,
                                                        f"blind_zone_edges{suffix}.png")
    body = _blind_html(metrics, bands, cases, groups, figures)
    return html_page("Blind-zone study", body), figures


def _blind_recall_figure(out_dir, samples, bands, speeds, cases, group, v_th, noise_free, name):
    method = group[0]
    cols = 2 if noise_free else 1
    fig, axes = plt.subplots(len(speeds), cols, figsize=(6.6 * cols, 2.5 * len(speeds) + 0.8), squeeze=False,
                             sharey=True)
    for r, v in enumerate(speeds):
        at_speed = (bands["speed_mps"] == v) & (bands["method"] == method)
        edges = np.concatenate([bands["measured_lower_deg"][at_speed], bands["measured_upper_deg"][at_speed]])
        edges = edges[np.isfinite(edges)]
        half = max(6.0, np.max(np.abs(edges - 90.0)) + 4.0) if edges.size else 12.0
        lo, hi = max(0.0, 90.0 - half), min(180.0, 90.0 + half)
        theory_lo = np.degrees(np.arccos(min(1.0, v_th / v)))
        for c in range(cols):
            ax = axes[r][c]
            key = f"recall_{method}" if c == 0 else f"recall_noise_free_{method}"
            ax.axvspan(theory_lo, 180.0 - theory_lo, color="#7f7f7f", alpha=0.25, lw=0,
                       label="Eq. 15 band |v cos φ| < v_th")
            for k, (t, d) in enumerate(cases):
                sel = (samples["target"] == t) & (samples["distance_m"] == d) & (samples["speed_mps"] == v)
                order = np.argsort(samples["phi_deg"][sel])
                ax.plot(samples["phi_deg"][sel][order], samples[key][sel][order], "-", lw=1.4,
                        color=_curve_colour(t, d, k), label=_curve_label(t, d), marker=".", ms=2.5)
            ax.set_xlim(lo, hi)
            ax.set_ylim(-0.03, 1.03)
            ax.axhline(0.5, color="k", lw=0.6, ls=":")
            if r == 0:
                ax.set_title("Table I noise (0.031 m/s Doppler)" if c == 0 else "noise-free Doppler", fontsize=10.5)
            ax.text(0.01, 0.06, f"v = {v:g} m/s", transform=ax.transAxes, fontsize=10, weight="bold",
                    bbox=dict(facecolor="white", alpha=0.8, lw=0))
            if c == 0:
                ax.set_ylabel("recall\n(object pixels\nlabelled moving)")
            if r == len(speeds) - 1:
                ax.set_xlabel("heading φ relative to the beam [deg] (90 = across)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=len(labels), fontsize=9, bbox_to_anchor=(0.5, 0.0))
    fig.suptitle(f"Detection recall against heading, {' = '.join(group)} (v_th = {v_th} m/s); grey: Eq. 15; dotted: "
                 "the 0.5 level that defines a band edge", fontsize=11)
    fig.tight_layout(rect=(0, 0.035, 1, 0.975))
    return save_figure(fig, out_dir, name)


def _blind_edges_figure(out_dir, bands, speeds, cases, group, v_th, name):
    method = group[0]
    fig, ax = plt.subplots(figsize=(9, 5.2))
    v = np.logspace(np.log10(min(speeds) * 0.8), np.log10(max(speeds) * 1.25), 200)
    theory = 90.0 - np.degrees(np.arccos(np.minimum(1.0, v_th / v)))
    ax.plot(v, theory, "k-", lw=2.2, label="Eq. 15: 90° − acos(v_th / v)")
    offsets = np.linspace(-0.04, 0.04, max(1, len(cases)))
    for k, (t, d) in enumerate(cases):
        sel = (bands["target"] == t) & (bands["distance_m"] == d) & (bands["method"] == method)
        c = _curve_colour(t, d, k)
        for noise, marker, fill in [("table1", "o", True), ("none", "s", False)]:
            s = sel & (bands["noise"] == noise)
            if not s.any():
                continue
            half = 0.5 * (bands["measured_upper_deg"][s] - bands["measured_lower_deg"][s])
            x = bands["speed_mps"][s] * (1 + offsets[k])
            ax.plot(x, half, ls="-" if fill else "--", marker=marker, color=c, mfc=c if fill else "white", lw=1.2,
                    ms=6, label=f"{_curve_label(t, d)}, {'Table I noise' if fill else 'noise-free'}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xticks(speeds)
    ax.set_xticklabels([f"{s:g}" for s in speeds])
    ax.set_xlabel("object speed v [m/s]")
    ax.set_ylabel("blind band half-width [deg]\n(measured: half of upper − lower edge)")
    ax.set_title(f"Half-width of the Doppler blind band around 90°, {' = '.join(group)}: measured against Eq. 15 "
                 "(missing markers: no band)", fontsize=10.5)
    ax.legend(fontsize=8, loc="lower left", ncol=2)
    fig.tight_layout()
    return save_figure(fig, out_dir, name)


def _effective_threshold(bands, k):
    """The v_th that Eq. 15 would need to give the measured lower edge once the object-size part
    (theory − silhouette) is taken out: v cos(lower + theory − silhouette)."""
    lo, tlo, slo = bands["measured_lower_deg"][k], bands["theory_lower_deg"][k], bands["silhouette_lower_deg"][k]
    if not np.isfinite([lo, tlo, slo]).all():
        return "–"
    return f"{bands['speed_mps'][k] * np.cos(np.radians(lo + tlo - slo)):.3f}"


def _band_rows(bands, group):
    sel = bands["method"] == group[0]
    rows, classes = [], []
    for k in np.where(sel)[0]:
        lo, hi = bands["measured_lower_deg"][k], bands["measured_upper_deg"][k]
        tlo, thi = bands["theory_lower_deg"][k], bands["theory_upper_deg"][k]
        slo, shi = bands["silhouette_lower_deg"][k], bands["silhouette_upper_deg"][k]
        found = bands["found"][k] == 1
        dlo, dhi = lo - tlo, hi - thi
        if found:
            worst = np.nanmax(np.abs([dlo, dhi])) if np.isfinite([dlo, dhi]).any() else np.nan
            measured, diff = f"{fmt(lo, 4)} – {fmt(hi, 4)}", f"{dlo:+.2f} / {dhi:+.2f}"
            cls = "pass" if worst <= 1.0 else "fail"
        else:
            measured, diff, cls = "no band (recall ≥ 0.5 at every heading)", "–", None
        rows.append([esc(" = ".join(group)), esc(_curve_label(bands["target"][k], bands["distance_m"][k])),
                     f"{bands['speed_mps'][k]:g}", "Table I" if bands["noise"][k] == "table1" else "none",
                     f"{tlo:.2f} – {thi:.2f}", measured, diff, f"{fmt(slo, 4)} – {fmt(shi, 4)}",
                     _effective_threshold(bands, k) if found else "–"])
        classes.append([None] * 6 + [cls] + [None, None])
    return rows, classes


def _example_lines(bands, cases, group, tlo, thi):
    lines = []
    for t, d in cases:
        for noise, text in [("none", "noise-free"), ("table1", "Table I noise")]:
            s = ((bands["method"] == group[0]) & (bands["target"] == t) & (bands["distance_m"] == d) &
                 (bands["speed_mps"] == 5.0) & (bands["noise"] == noise))
            if not s.any():
                continue
            k = np.where(s)[0][0]
            lo, hi = bands["measured_lower_deg"][k], bands["measured_upper_deg"][k]
            if bands["found"][k] != 1:
                lines.append(f"<li>{esc(_curve_label(t, d))}, {text}: no blind band</li>")
                continue
            lines.append(f"<li>{esc(_curve_label(t, d))}, {text}: {fmt(lo, 4)}° to {fmt(hi, 4)}° "
                         f"({lo - tlo:+.2f}° / {hi - thi:+.2f}° from Eq. 15)</li>")
    return lines


def _blind_html(metrics, bands, cases, groups, figures):
    p = metrics["params"]
    v_th = p["velocity_threshold_mps"]
    example = metrics["paper_example"]
    tlo, thi = example["theory_band_deg"]
    lines = [f"<p>The paper: for 5 m/s the blind band is about 88° to 92° (Eq. 15 with v_th = 0.17 m/s gives "
             f"{tlo:.2f}° to {thi:.2f}°). Measured here at 5 m/s:</p>"]
    rows, classes = [], []
    for g in groups:
        lines.append(f"<p><code>{esc(' = '.join(g))}</code>:</p><ul>" + "".join(_example_lines(bands, cases, g, tlo, thi))
                     + "</ul>")
        r, c = _band_rows(bands, g)
        rows += r
        classes += c
    table = html_table(["methods", "target", "v [m/s]", "noise", "Eq. 15 band [deg]", "measured band [deg]",
                        "measured − Eq. 15, lower / upper [deg]", "Eq. 15 at the silhouette [deg]",
                        "effective v_th [m/s]"], rows, name_columns=2, classes=classes)
    body = ["<h1>Doppler blind zone (Eq. 15): measured against theory</h1>",
            f"<p class=\"small\">A static sensor head (40°×30°, 0.2° pixels) {p['sensor_height_m']:g} m above the "
            f"ground, v_th = {v_th} m/s, a far wall {p['wall_gap_m']:g} m behind the object, one box moving at speed "
            "v with heading φ from the beam towards its centre (φ = 90°: across). Recall = the object's pixels "
            f"labelled moving. A band edge is where recall crosses {p['recall_level']}; coarse step "
            f"{p['phi_step_deg']}°, fine step {p['fine_step_deg']}° near narrow bands, then "
            f"{p['refine_iterations']} bisection steps per edge. Methods with identical recall everywhere are "
            f"shown once (a = b); {metrics['samples']} frames in {metrics['seconds']:.0f} s.</p>",
            "<h2>The paper's example</h2>", "".join(lines),
            "<h2>Where measurement and theory disagree, and by how much</h2>",
            "<ul><li><b>Object size.</b> Region growing is transitive: once any pixel pair on the object's "
            "silhouette differs from the background by less than v_th, the whole object joins the static region. "
            "The beams across an object see headings spread by its angular size, so the band widens by about the "
            "object's half-width as seen from the sensor: several degrees for a car at 10–40 m (a 4.5 m car "
            "broadside at 10 m spans ±13°). Eq. 15 evaluated at the silhouette pixels (column \"Eq. 15 at the "
            "silhouette\") predicts the noise-free measurement of the region-growing methods to within the "
            "sampling step.</li>"
            "<li><b>Noise.</b> With Table I noise each silhouette pair's Doppler difference scatters by about "
            "0.031·√2 = 0.044 m/s, and among tens to hundreds of pairs one usually falls under v_th: the band "
            "widens further, as if v_th were larger. The last column gives that effective v_th: the threshold Eq. 15 "
            "would need to put the lower edge where it was measured, once the object-size part (Eq. 15 minus the "
            "silhouette prediction) is taken out; noise-free rows of the region-growing methods give 0.17 m/s by "
            "construction. The effect in degrees grows as the speed falls.</li>"
            "<li>Methods that do not grow regions from the background (e.g. one that labels each point by its "
            "own ego-compensated Doppler) lose only the pixels inside the band, not the whole object, and may "
            "show no band at all for large objects (recall stays above 0.5).</li>"
            "<li>Rows in red differ from Eq. 15 by more than 1° on an edge.</li></ul>",
            "<h2>Band edges</h2>", table]
    for k, g in enumerate(groups):
        suffix = "" if k == 0 else f"_{g[0]}"
        label = esc(" = ".join(g))
        body.append(html_figure(figures[f"recall{suffix}"],
                                f"{label}: recall of the object's pixels against heading, one row per speed; left with "
                                "Table I noise, right with noise-free Doppler; grey: Eq. 15."))
        body.append(html_figure(figures[f"edges{suffix}"],
                                f"{label}: half-width of the blind band against speed: Eq. 15 (line) and measured "
                                "(markers; filled: with noise, hollow: noise-free)."))
    return "\n".join(body)
