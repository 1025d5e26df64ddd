#!/usr/bin/python3
"""Draws the figures and writes report.html for a folder written by `fmcw evaluate` (of a dataset
or of a folder of datasets), `fmcw run` or `fmcw study ...`: DIR/metrics.json says which ("kind")
and names the tables beside it.

Usage: /usr/bin/python3 tools/report/fmcw_report.py DIR

Every file is written under a temporary name and renamed; report.html comes last. On bad input
the script prints one line, "fmcw_report: error: <file>: <what>", and exits with status 1.
"""

import os
import sys

sys.dont_write_bytecode = True  # the source tree may be read-only
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from report_common import ReportError, load_json, write_text  # noqa: E402


def report_evaluation(out_dir, metrics):
    import evaluation_figures
    import evaluation_html

    data = evaluation_figures.EvaluationData(out_dir, metrics)
    figures = evaluation_figures.draw_all(data)
    return evaluation_html.build_html(data, figures), figures


def report_aggregate(out_dir, metrics):
    import aggregate_report

    return aggregate_report.report(out_dir, metrics)


def report_study(out_dir, metrics):
    import study_blind_zone
    import study_sweeps

    kind = metrics["kind"]
    if kind == "blind_zone":
        return study_blind_zone.report(out_dir, metrics)
    if kind == "threshold":
        return study_sweeps.threshold(out_dir, metrics)
    return study_sweeps.object_points(out_dir, metrics)


def main(argv):
    if len(argv) != 2:
        print("usage: fmcw_report.py DIR", file=sys.stderr)
        return 2
    out_dir = argv[1]
    try:
        metrics_path = os.path.join(out_dir, "metrics.json")
        metrics = load_json(metrics_path)
        kind = metrics.get("kind")
        if kind == "evaluation":
            page, figures = report_evaluation(out_dir, metrics)
        elif kind == "aggregate":
            page, figures = report_aggregate(out_dir, metrics)
        elif kind in ("blind_zone", "threshold", "object_points"):
            page, figures = report_study(out_dir, metrics)
        else:
            raise ReportError(f"{metrics_path}: unknown report kind {kind!r}")
        write_text(out_dir, "report.html", page)
    except ReportError as e:
        print(f"fmcw_report: error: {e}", file=sys.stderr)
        return 1
    except (KeyError, ValueError, IndexError) as e:
        print(f"fmcw_report: error: {out_dir}: unexpected table or metrics content ({type(e).__name__}: {e})",
              file=sys.stderr)
        return 1
    drawn = [f for f in figures.values() if f]
    print(f"report: {len(drawn)} figures and report.html in {out_dir}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
