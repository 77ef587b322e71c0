"""What a `pbf run` output directory holds (docs/clients.md), and which of its
frames a Blender scene frame shows."""

import bisect
import csv
import json
import math
import os
import re


class RunError(ValueError):
    """A run directory or file the add-on cannot use; the message names it."""


def _numbered(directory, pattern):
    """{frame: path} of the files in `directory` whose name matches `pattern`
    (one group: the frame number)."""
    found = {}
    if os.path.isdir(directory):
        for name in os.listdir(directory):
            m = re.fullmatch(pattern, name)
            if m:
                found[int(m.group(1))] = os.path.join(directory, name)
    return found


class Sequence:
    """Frame-numbered files of one kind, e.g. frame_00042.ply."""

    def __init__(self, directory, pattern):
        self.directory = directory
        self.pattern = pattern
        self.rescan()

    def rescan(self):
        self.files = _numbered(self.directory, self.pattern)
        self.frames = sorted(self.files)

    def at_or_before(self, frame):
        """The latest available frame <= `frame` (the first one before it), or None.
        A run still being written gains frames: look again past the end."""
        if self.frames and frame > self.frames[-1]:
            self.rescan()
        if not self.frames:
            return None
        i = bisect.bisect_right(self.frames, frame)
        return self.frames[max(i - 1, 0)]

    def __bool__(self):
        return bool(self.frames)


class RunDirectory:
    """The files of one run: particle frames (PLY), surfaces (PLY, else OBJ),
    level sets (.vdb) in surface/, bodies.csv, and fps / particle radius."""

    def __init__(self, directory, fps=0.0):
        directory = os.path.abspath(bpy_path(directory))
        if not os.path.isdir(directory):
            raise RunError(f"{directory}: no such directory (expected the output of `pbf run`)")
        self.directory = directory
        surface = os.path.join(directory, "surface")
        self.particles = Sequence(directory, r"frame_(\d{5,})\.ply")
        self.surfaces = Sequence(surface, r"surface_(\d{5,})\.ply")
        if not self.surfaces:
            self.surfaces = Sequence(surface, r"surface_(\d{5,})\.obj")
        self.level_sets = Sequence(surface, r"levelset_(\d{5,})\.vdb")
        bodies = os.path.join(directory, "bodies.csv")
        self.bodies = bodies if os.path.isfile(bodies) else None
        if not (self.particles or self.surfaces or self.level_sets or self.bodies):
            raise RunError(f"{directory}: no pbf frames (frame_NNNNN.ply, surface/surface_NNNNN.ply, "
                           "surface/levelset_NNNNN.vdb) and no bodies.csv")
        summary = self._summary()
        self.fps = fps if fps > 0 else self._fps(summary)
        self.particle_radius = float(summary.get("particle_radius", 0.0) or 0.0)

    def _summary(self):
        path = os.path.join(self.directory, "summary.json")
        if not os.path.isfile(path):
            return {}
        try:
            with open(path) as f:
                summary = json.load(f)
        except (OSError, ValueError) as e:
            raise RunError(f"{path}: not valid JSON ({e})") from None
        if not isinstance(summary, dict):
            raise RunError(f"{path}: not a JSON object")
        return summary

    def _fps(self, summary):
        """summary.json's fps; else, for a run killed before it wrote one,
        the time of frame 1 in stats.csv."""
        fps = summary.get("fps")
        if fps is not None:
            if not isinstance(fps, (int, float)) or not fps > 0:
                raise RunError(f"{os.path.join(self.directory, 'summary.json')}: fps: "
                               f"must be a positive number, got {fps!r}")
            return float(fps)
        stats = os.path.join(self.directory, "stats.csv")
        if os.path.isfile(stats):
            with open(stats, newline="") as f:
                for row in csv.DictReader(f):
                    try:
                        frame, time = int(row["frame"]), float(row["time"])
                    except (KeyError, TypeError, ValueError):
                        raise RunError(f"{stats}: no numeric frame and time columns") from None
                    if frame > 0 and time > 0:
                        return frame / time
        raise RunError(f"{self.directory}: no fps in summary.json and no frame times in "
                       "stats.csv: give the run's frames per second (fps)")


def bpy_path(path):
    """Blender's '//relative' paths made absolute (plain paths unchanged)."""
    try:
        import bpy
        return bpy.path.abspath(path)
    except ImportError:
        return path


def scene_fps(scene):
    return scene.render.fps / scene.render.fps_base


def run_frame(scene_frame, frame_start, fps_scene, fps_run):
    """The run frame shown at `scene_frame`: the last one whose time
    k / fps_run is not after the scene time (scene_frame - frame_start) / fps_scene."""
    time = (scene_frame - frame_start) / fps_scene
    return max(0, math.floor(time * fps_run + 1e-6))


def scene_frame(time, frame_start, fps_scene):
    """The (fractional) scene frame at run time `time`."""
    return frame_start + time * fps_scene
