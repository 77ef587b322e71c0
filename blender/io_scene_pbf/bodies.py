"""Rigid-body poses from a run's bodies.csv, as keyframed empties.

The columns start `frame,time,body,x,y,z,qw,qx,qy,qz` (position in metres,
orientation as a unit quaternion, pbf's Y-up axes); more columns (velocities)
may follow and are not needed for the poses.
"""

import csv

from .run_dir import RunError

COLUMNS = ("frame", "time", "body", "x", "y", "z", "qw", "qx", "qy", "qz")


def read_bodies(path):
    """{body id: [(time, (x, y, z), (qw, qx, qy, qz)), ...]} in file order."""
    bodies = {}
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header is None or tuple(h.strip() for h in header[: len(COLUMNS)]) != COLUMNS:
            raise RunError(f"{path}: the header must start with {','.join(COLUMNS)}")
        for line, row in enumerate(reader, start=2):
            if not row:
                continue
            if len(row) < len(COLUMNS):
                raise RunError(f"{path}:{line}: {len(row)} columns, expected at least {len(COLUMNS)}")
            try:
                values = [float(v) for v in row[3:10]]
                time, body = float(row[1]), int(row[2])
            except ValueError:
                raise RunError(f"{path}:{line}: time, body, x..qz must be numbers") from None
            bodies.setdefault(body, []).append((time, tuple(values[:3]), tuple(values[3:7])))
    if not bodies:
        raise RunError(f"{path}: no rows")
    return bodies


def keyframe_body(obj, samples, to_scene_frame):
    """Linear keyframes of location and rotation_quaternion at the scene
    frames of the samples' times (fractional frames when the frame rates differ)."""
    obj.rotation_mode = "QUATERNION"
    obj.animation_data_create()
    import bpy
    action = bpy.data.actions.new(obj.name + " poses")
    obj.animation_data.action = action
    frames = [to_scene_frame(t) for t, _, _ in samples]
    for path, column, size in (("location", 1, 3), ("rotation_quaternion", 2, 4)):
        for i in range(size):
            curve = action.fcurves.new(path, index=i)
            curve.keyframe_points.add(len(samples))
            co = []
            for frame, sample in zip(frames, samples):
                co += [frame, sample[column][i]]
            curve.keyframe_points.foreach_set("co", co)
            curve.keyframe_points.foreach_set("interpolation", [1] * len(samples))  # LINEAR
            curve.update()
