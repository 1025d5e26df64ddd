"""Shared helpers of the report scripts: tables, atomic files, colours, HTML pieces."""

import csv
import html
import json
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

# One colour per method, the same in every figure; the baseline first.
METHOD_COLOURS = {"paper": "#1f77b4", "fast": "#ff7f0e", "robust": "#2ca02c"}
EXTRA_COLOURS = ["#d62728", "#9467bd", "#8c564b", "#e377c2"]
METHOD_STYLES = {"paper": "-", "fast": "--", "robust": "-."}

plt.rcParams.update({
    "figure.dpi": 100,
    "savefig.dpi": 110,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "axes.spines.top": False,
    "axes.spines.right": False,
    "font.size": 10,
    "axes.titlesize": 11,
    "legend.fontsize": 9,
    "legend.framealpha": 0.85,
})


def method_colour(method, order):
    if method in METHOD_COLOURS:
        return METHOD_COLOURS[method]
    extras = [m for m in order if m not in METHOD_COLOURS]
    return EXTRA_COLOURS[extras.index(method) % len(EXTRA_COLOURS)] if method in extras else "#7f7f7f"


def method_style(method):
    return METHOD_STYLES.get(method, "-.")


class ReportError(Exception):
    """A problem with the report's input, reported as one line naming the file."""


def load_json(path):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except FileNotFoundError:
        raise ReportError(f"{path}: missing")
    except json.JSONDecodeError as e:
        raise ReportError(f"{path}:{e.lineno}: malformed JSON: {e.msg}")


def read_table(path):
    """A CSV written by the C++ side as {column: numpy array}; numeric columns become float
    arrays (nan where the cell says nan), the others stay strings."""
    try:
        with open(path, newline="", encoding="utf-8") as f:
            reader = csv.reader(f)
            header = next(reader, None)
            if header is None:
                raise ReportError(f"{path}: empty table (no header)")
            rows = list(reader)
    except FileNotFoundError:
        raise ReportError(f"{path}: missing")
    for k, row in enumerate(rows):
        if len(row) != len(header):
            raise ReportError(f"{path}:{k + 2}: {len(row)} cells, header has {len(header)}")
    table = {}
    for c, name in enumerate(header):
        cells = [row[c] for row in rows]
        try:
            table[name] = np.array([float(x) for x in cells], dtype=float)
        except ValueError:
            table[name] = np.array(cells, dtype=object)
    table["_rows"] = len(rows)
    return table


def select(table, mask):
    return {k: (v[mask] if isinstance(v, np.ndarray) else v) for k, v in table.items()}


def save_figure(fig, out_dir, name):
    """Saves a PNG under a temporary name and renames it, so a reader never sees half a file."""
    path = os.path.join(out_dir, name)
    tmp = os.path.join(out_dir, f".tmp.{name}.{os.getpid()}.png")
    try:
        fig.savefig(tmp, format="png", bbox_inches="tight")
        os.replace(tmp, path)
    finally:
        plt.close(fig)
        if os.path.exists(tmp):
            os.remove(tmp)
    return name


def write_text(out_dir, name, text):
    path = os.path.join(out_dir, name)
    tmp = os.path.join(out_dir, f".tmp.{name}.{os.getpid()}")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def fmt(value, digits=4, unit=""):
    """A number for tables: '–' for missing values."""
    if value is None or (isinstance(value, float) and not np.isfinite(value)):
        return "–"
    if isinstance(value, (int, np.integer)):
        return f"{value:,}{unit}"
    return f"{value:.{digits}g}{unit}"


def esc(text):
    return html.escape(str(text))


HTML_STYLE = """
body { font-family: 'DejaVu Sans', Arial, sans-serif; max-width: 1250px; margin: 2em auto; color: #222;
       line-height: 1.45; padding: 0 1em; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: 0.2em; margin-top: 1.8em; }
table { border-collapse: collapse; margin: 0.8em 0; font-size: 0.92em; }
th, td { border: 1px solid #ccc; padding: 0.3em 0.7em; text-align: right; }
th { background: #f3f3f3; } td.name, th.name { text-align: left; }
td.pass { background: #e6f4e6; } td.fail { background: #fbe3e3; font-weight: bold; }
.missed { background: #fff4e5; border-left: 4px solid #e69500; padding: 0.6em 1em; }
.ok { background: #eef8ee; border-left: 4px solid #3a3; padding: 0.6em 1em; }
figure { margin: 1.2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.92em; color: #444; margin-top: 0.3em; }
code { background: #f4f4f4; padding: 0 0.25em; } .small { font-size: 0.88em; color: #555; }
"""


def html_page(title, body):
    return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{esc(title)}</title>"
            f"<style>{HTML_STYLE}</style></head><body>\n{body}\n</body></html>\n")


def html_figure(name, caption):
    return f'<figure><img src="{esc(name)}" alt="{esc(caption)}"><figcaption>{caption}</figcaption></figure>\n'


def html_table(header, rows, name_columns=1, classes=None):
    """rows: lists of cell strings (already escaped); classes: same shape, CSS class or None."""
    out = ["<table><tr>"]
    out += [f'<th class="name">{h}</th>' if i < name_columns else f"<th>{h}</th>" for i, h in enumerate(header)]
    out.append("</tr>")
    for r, row in enumerate(rows):
        out.append("<tr>")
        for i, cell in enumerate(row):
            cls = "name" if i < name_columns else (classes[r][i] if classes and classes[r][i] else "")
            out.append(f'<td class="{cls}">{cell}</td>' if cls else f"<td>{cell}</td>")
        out.append("</tr>")
    out.append("</table>")
    return "".join(out) + "\n"
