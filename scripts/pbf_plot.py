#!/usr/bin/python3
"""Draws pbf's figures with matplotlib: the one plotting path of `pbf plot`,
`pbf run` and `pbf validate` (include/pbf/run/plot.hpp writes the data, this
script only draws it).

usage: pbf_plot.py DATA.plot.json OUT.png [DATA.plot.json OUT.png ...]

A data file is JSON: {"title", "columns", "panels": [{"title", "x_label",
"y_label", "log_y", "series": [{"label", "x", "y", "style"}]}]} with style
"line", "dashed" or "points"; null values are gaps. Each PNG is written to a
temporary file and renamed into place.

Exit status: 0 all drawn; 3 matplotlib is not installed (Debian package
python3-matplotlib); 1 anything else (the message says which file).
"""

import json
import math
import os
import sys

EXIT_MISSING_MATPLOTLIB = 3

STYLES = {
    "line": {"linestyle": "-", "marker": None},
    "dashed": {"linestyle": "--", "marker": None},
    "points": {"linestyle": "none", "marker": "o", "markersize": 4},
}


def load(path):
    """The figure description in `path`, with null values as NaN."""
    with open(path, encoding="utf-8") as f:
        figure = json.load(f)
    for panel in figure["panels"]:
        for series in panel["series"]:
            for axis in ("x", "y"):
                series[axis] = [math.nan if v is None else float(v) for v in series[axis]]
            if len(series["x"]) != len(series["y"]):
                raise ValueError(f"{path}: series '{series['label']}': x and y differ in length")
            if series.get("style", "line") not in STYLES:
                raise ValueError(f"{path}: series '{series['label']}': unknown style "
                                 f"'{series['style']}'")
    return figure


def draw(figure):
    """A matplotlib Figure of the description (as load returns it)."""
    import matplotlib.pyplot as plt

    panels = figure["panels"]
    columns = max(1, min(int(figure.get("columns", 2)), len(panels)))
    rows = max(1, math.ceil(len(panels) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(6.0 * columns, 3.6 * rows), squeeze=False)
    for k, ax in enumerate(axes.flat):
        if k >= len(panels):
            ax.set_visible(False)
            continue
        panel = panels[k]
        for series in panel["series"]:
            ax.plot(series["x"], series["y"], label=series["label"],
                    **STYLES[series.get("style", "line")])
        ax.set_title(panel["title"], fontsize=10)
        ax.set_xlabel(panel["x_label"])
        ax.set_ylabel(panel["y_label"])
        if panel.get("log_y"):
            ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
        if len(panel["series"]) > 1:
            ax.legend(fontsize=8)
    fig.suptitle(figure["title"], fontsize=12)
    fig.tight_layout()
    return fig


def save(fig, png):
    """Writes the PNG whole: a temporary file beside it, then a rename."""
    directory = os.path.dirname(os.path.abspath(png))
    temporary = os.path.join(directory, f".{os.path.basename(png)}.tmp{os.getpid()}")
    try:
        fig.savefig(temporary, format="png", dpi=100)
        os.replace(temporary, png)
    finally:
        if os.path.exists(temporary):
            os.remove(temporary)


def main(argv):
    if len(argv) < 2 or len(argv) % 2 != 0:
        print(__doc__, file=sys.stderr)
        return 1
    try:
        import matplotlib
        matplotlib.use("Agg")  # no display needed
        import matplotlib.pyplot as plt
    except ImportError as e:
        print(f"pbf_plot.py: matplotlib is not installed ({e}): "
              "apt-get install python3-matplotlib", file=sys.stderr)
        return EXIT_MISSING_MATPLOTLIB
    for data, png in zip(argv[0::2], argv[1::2]):
        try:
            fig = draw(load(data))
            save(fig, png)
            plt.close(fig)
        except (OSError, ValueError, KeyError, TypeError) as e:
            print(f"pbf_plot.py: {data} -> {png}: {e}", file=sys.stderr)
            return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
