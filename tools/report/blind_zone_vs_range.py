#!/usr/bin/env python3
"""The Doppler blind band against range under two measurement models, from two
`fmcw study blind-zone` runs that differ only in --measurement-model (docs/SIMULATOR.md):

    fmcw study blind-zone --measurement-model gaussian --speeds 10 --distances 20,50,80,110,140 \\
        --no-small --methods fast --no-figures -o GAUSS
    fmcw study blind-zone --measurement-model snr ... -o SNR
    blind_zone_vs_range.py GAUSS SNR -o blind_zone_vs_range.png

Plots, per model, the measured band width (upper minus lower edge, where recall crosses 0.5) and
the recall at the band's centre (heading 90 deg), against the distance of the car-sized box;
prints the numbers it plots."""

import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def band_widths(study_dir, method):
    """{distance: (width_deg, theory_width_deg)} of the noisy curves of one method."""
    out = {}
    for row in read_rows(os.path.join(study_dir, "blind_zone_bands.csv")):
        if row["method"] != method or row["noise"] == "none":
            continue
        d = float(row["distance_m"])
        width = float(row["measured_upper_deg"]) - float(row["measured_lower_deg"]) if row["found"] in ("1", "true", "yes") else float("nan")
        theory = float(row["theory_upper_deg"]) - float(row["theory_lower_deg"])
        out[d] = (width, theory)
    return out


def centre_recall(study_dir, method):
    """{distance: recall at the heading nearest 90 deg, the band's centre (0 where the band holds)}."""
    best = {}
    for row in read_rows(os.path.join(study_dir, "blind_zone_samples.csv")):
        d = float(row["distance_m"])
        off = abs(float(row["phi_deg"]) - 90.0)
        if d not in best or off < best[d][0]:
            best[d] = (off, float(row[f"recall_{method}"]))
    return {d: r for d, (_, r) in best.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("gaussian_dir")
    ap.add_argument("snr_dir")
    ap.add_argument("--method", default="fast")
    ap.add_argument("-o", "--output", required=True)
    a = ap.parse_args()
    fig, (ax_w, ax_r) = plt.subplots(1, 2, figsize=(10, 4))
    print("model     distance_m  band_width_deg  theory_deg  recall_at_90deg")
    for name, d, style in (("gaussian", a.gaussian_dir, "o-"), ("snr", a.snr_dir, "s-")):
        widths = band_widths(d, a.method)
        recall = centre_recall(d, a.method)
        xs = sorted(widths)
        ax_w.plot(xs, [widths[x][0] for x in xs], style, label=f"{name}: measured")
        ax_r.plot(xs, [recall.get(x, float("nan")) for x in xs], style, label=name)
        if name == "gaussian":
            ax_w.plot(xs, [widths[x][1] for x in xs], "k--", label="Eq. 15 (beam to the centre)")
        for x in xs:
            print(f"{name:9s} {x:10.0f}  {widths[x][0]:14.2f}  {widths[x][1]:10.2f}  {recall.get(x, float('nan')):15.3f}")
    ax_w.set_xlabel("distance of the car-sized box [m]")
    ax_w.set_ylabel("blind band width [deg]")
    ax_w.legend()
    ax_w.grid(alpha=0.3)
    ax_r.set_xlabel("distance of the car-sized box [m]")
    ax_r.set_ylabel("recall at heading 90 deg (band centre)")
    ax_r.set_ylim(0, 1.05)
    ax_r.legend()
    ax_r.grid(alpha=0.3)
    fig.suptitle(f"Doppler blind band against range, method {a.method}")
    fig.tight_layout()
    fig.savefig(a.output, dpi=120)
    return 0


if __name__ == "__main__":
    sys.exit(main())
