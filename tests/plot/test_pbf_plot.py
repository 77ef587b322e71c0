"""The plotting path (scripts/pbf_plot.py, include/pbf/run/plot.hpp): the plot of
a run shows stats.csv's numbers, the script draws exactly the data it is
given, and says what to install when matplotlib is missing.

Run by CTest (test plot.script) after the fixture run.default_scene, with
PBF_RUN_DIR set to that run's directory; `pytest tests/plot` alone runs the
tests that need no run.
"""

import csv
import json
import math
import os
import pathlib
import subprocess
import sys

import pytest

SOURCE = pathlib.Path(__file__).resolve().parents[2]
SCRIPT = SOURCE / "scripts" / "pbf_plot.py"
sys.path.insert(0, str(SCRIPT.parent))

# The stats.csv column each series of the run's plot must show, and the
# factor between them (density errors are plotted in per cent).
EXPECTED_SERIES = {
    ("Density error", "average"): ("avg_density_error", 100.0),
    ("Density error", "maximum"): ("max_density_error", 100.0),
    ("Kinetic energy", "1/2 m sum |v|^2"): ("kinetic_energy", 1.0),
    ("Particles", "count"): ("particles", 1.0),
    ("Substeps per frame", "substeps"): ("substeps", 1.0),
    ("Wall-clock time per substep", "whole step"): ("step_ms", 1.0),
    ("Wall-clock time per substep", "neighbour search"): ("neighbor_ms", 1.0),
    ("Wall-clock time per substep", "density solve"): ("solve_ms", 1.0),
    ("Wall-clock time per substep", "predict + post-process"): ("post_ms", 1.0),
    ("Fastest particle", "max |v|"): ("max_speed", 1.0),
}


PER_STEP = {"substeps", "step_ms", "neighbor_ms", "solve_ms", "post_ms"}


def run_dir():
    directory = os.environ.get("PBF_RUN_DIR")
    if not directory:
        pytest.skip("PBF_RUN_DIR is not set (run through ctest: plot.script)")
    return pathlib.Path(directory)


def read_stats(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    assert rows, f"{path}: no rows"
    return {name: [float(row[name]) for row in rows] for name in rows[0]}


def test_the_plot_of_a_run_shows_stats_csv():
    directory = run_dir()
    stats = read_stats(directory / "stats.csv")
    with open(directory / "stats.plot.json") as f:
        figure = json.load(f)
    assert figure["title"].startswith("dam_break: ")
    seen = set()
    for panel in figure["panels"]:
        assert panel["x_label"] == "simulated time (s)"
        assert "(" in panel["y_label"] or panel["y_label"] in ("particles", "substeps"), \
            f"no unit in {panel['y_label']!r}"
        for series in panel["series"]:
            key = next((k for k in EXPECTED_SERIES
                        if panel["title"].startswith(k[0]) and series["label"] == k[1]), None)
            assert key is not None, f"unexpected series {panel['title']!r} / {series['label']!r}"
            column, factor = EXPECTED_SERIES[key]
            # Substeps and step times exist for frames that stepped (not frame 0).
            rows = [k for k in range(len(stats["time"]))
                    if column not in PER_STEP or stats["substeps"][k] > 0]
            assert series["x"] == pytest.approx([stats["time"][k] for k in rows], rel=1e-12)
            assert series["y"] == pytest.approx([factor * stats[column][k] for k in rows],
                                                rel=1e-12), \
                f"{key} does not show stats.csv's {column}"
            seen.add(key)
    assert seen == set(EXPECTED_SERIES), f"missing: {set(EXPECTED_SERIES) - seen}"


def write_figure(path):
    figure = {
        "title": "test figure",
        "columns": 2,
        "panels": [
            {"title": "a", "x_label": "t (s)", "y_label": "y (m)", "log_y": False,
             "series": [{"label": "line", "x": [0, 1, 2], "y": [1, 4, 9], "style": "line"},
                        {"label": "gap", "x": [0, 1, 2], "y": [2, None, 3], "style": "dashed"}]},
            {"title": "b", "x_label": "T", "y_label": "Z", "log_y": True,
             "series": [{"label": "data", "x": [0.5, 1.5], "y": [1.1, 2.2], "style": "points"}]},
            {"title": "c", "x_label": "x", "y_label": "y", "log_y": False,
             "series": [{"label": "only", "x": [1], "y": [1], "style": "line"}]},
        ],
    }
    path.write_text(json.dumps(figure))
    return figure


def test_the_script_draws_exactly_the_data_it_is_given(tmp_path):
    pytest.importorskip("matplotlib")
    import pbf_plot

    spec = write_figure(tmp_path / "f.plot.json")
    fig = pbf_plot.draw(pbf_plot.load(tmp_path / "f.plot.json"))
    axes = [ax for ax in fig.axes if ax.get_visible()]
    assert len(axes) == len(spec["panels"])
    for ax, panel in zip(axes, spec["panels"]):
        assert ax.get_title() == panel["title"]
        assert ax.get_xlabel() == panel["x_label"]
        assert ax.get_ylabel() == panel["y_label"]
        assert ax.get_yscale() == ("log" if panel["log_y"] else "linear")
        lines = ax.get_lines()
        assert [line.get_label() for line in lines] == [s["label"] for s in panel["series"]]
        for line, series in zip(lines, panel["series"]):
            assert list(line.get_xdata()) == series["x"]
            for drawn, given in zip(line.get_ydata(), series["y"]):
                assert (math.isnan(drawn) and given is None) or drawn == given
            if series["style"] == "points":
                assert line.get_linestyle() == "None" and line.get_marker() == "o"
            elif series["style"] == "dashed":
                assert line.get_linestyle() == "--"


def test_the_script_writes_the_png_whole(tmp_path):
    pytest.importorskip("matplotlib")
    write_figure(tmp_path / "f.plot.json")
    png = tmp_path / "f.png"
    result = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "f.plot.json"), str(png)],
                            capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f.plot.json", "f.png"]


def test_bad_data_names_the_file(tmp_path):
    pytest.importorskip("matplotlib")
    (tmp_path / "bad.plot.json").write_text('{"title": "x", "panels": [{"series": '
                                            '[{"label": "s", "x": [1, 2], "y": [1]}]}]}')
    result = subprocess.run([sys.executable, str(SCRIPT), str(tmp_path / "bad.plot.json"),
                             str(tmp_path / "bad.png")], capture_output=True, text=True, timeout=120)
    assert result.returncode == 1
    assert "bad.plot.json" in result.stderr and "differ in length" in result.stderr
    assert not (tmp_path / "bad.png").exists()


def test_missing_matplotlib_says_what_to_install(tmp_path):
    write_figure(tmp_path / "f.plot.json")
    # -S: no site-packages, so no matplotlib (as without python3-matplotlib).
    result = subprocess.run(["/usr/bin/python3", "-S", str(SCRIPT), str(tmp_path / "f.plot.json"),
                             str(tmp_path / "f.png")], capture_output=True, text=True, timeout=60)
    assert result.returncode == 3
    assert "apt-get install python3-matplotlib" in result.stderr
    assert not (tmp_path / "f.png").exists()
