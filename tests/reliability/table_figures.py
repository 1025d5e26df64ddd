#!/usr/bin/env python3
"""The figures of docs/EVALUATION.md's eight-scenario table, at their printed precision, from a
folder of reports (one metrics.json per scenario, as tests/reliability/same_outputs.sh writes
them). Diff its output for two builds to see whether a change moved any printed figure.

    /usr/bin/python3 tests/reliability/table_figures.py REPORTS_FOLDER
"""
import json
import pathlib
import sys


def fmt(value, digits):
    return "n/a" if value is None else f"{value:.{digits}f}"


def main(folder):
    for metrics in sorted(pathlib.Path(folder).glob("*/metrics.json")):
        m = json.loads(metrics.read_text())
        for name in m["method_order"]:
            t = m["methods"][name]
            ego = t["ego_velocity"]
            obj = t["objects"]
            band = t.get("blind_zone", {})
            rmse = ego.get("rmse_mps") or [None, None, None]
            print(" | ".join([
                metrics.parent.name, name,
                fmt(t["motion"]["accuracy"], 4),
                f"{fmt(rmse[0], 3)} / {fmt(rmse[1], 3)}",
                fmt(ego.get("yaw_rate_rmse_dps"), 2),
                f"{fmt(obj.get('median_reference_error_mps_ge200'), 3)} ({fmt(obj.get('median_reference_error_mps_ge200_turning'), 2)})",
                f"{fmt(obj.get('instance_precision'), 2)} / {fmt(obj.get('instance_recall'), 2)}",
                fmt(band.get("recall_tracked"), 2),
            ]))


if __name__ == "__main__":
    main(sys.argv[1])
