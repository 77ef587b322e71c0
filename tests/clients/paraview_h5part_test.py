"""ParaView opens pbf's H5Part files as a user would (run with pvpython; CTest
test clients.paraview_h5part, after mpi.h5part_ranks wrote them with 4 MPI
ranks): ParaView's H5Part reader on frame_00012.h5part shows the step's time,
one point per particle at the written positions, and the point arrays vx, vy,
vz, density and id (64-bit) with the written values; on the index
particles.h5part it shows both frames as time steps at their times.
Usage: pvpython paraview_h5part_test.py DIR   (DIR holds the files and
expected.json, written by tests/io/h5part_mpi_test.cpp)
"""

import json
import os
import sys

import numpy as np
from paraview import servermanager
from paraview.simple import H5PartReader
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import VTK_LONG, VTK_LONG_LONG

directory = sys.argv[1]
expected = json.load(open(os.path.join(directory, "expected.json")))
failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL:", message)


def times(reader):
    """TimestepValues as a list (ParaView gives a bare float for one step)."""
    values = reader.TimestepValues
    try:
        return [float(v) for v in values]
    except TypeError:
        return [float(values)]


def fetch(reader, time):
    reader.UpdatePipeline(time)
    return servermanager.Fetch(reader)


frame_file = os.path.join(directory, "frame_00012.h5part")
frame = H5PartReader(FileName=frame_file)
check(times(frame) == [expected["time"]], f"{frame_file}: times {times(frame)}, expected [{expected['time']}]")
data = fetch(frame, expected["time"])
n = data.GetNumberOfPoints()
check(n == expected["particles"], f"{frame_file}: {n} points, expected {expected['particles']}")
point_data = data.GetPointData()
arrays = {point_data.GetArrayName(i): point_data.GetArray(i) for i in range(point_data.GetNumberOfArrays())}
wanted = {"x", "y", "z", "vx", "vy", "vz", "density", "id"}
check(set(arrays) == wanted, f"{frame_file}: point arrays {sorted(arrays)}, expected {sorted(wanted)}")
if n == expected["particles"] and set(arrays) == wanted:
    xyz = vtk_to_numpy(data.GetPoints().GetData())
    for c, name in enumerate("xyz"):
        check(np.array_equal(xyz[:, c], np.float32(expected[name])), f"{frame_file}: points' {name} differ")
    for name in ["vx", "vy", "vz", "density"]:
        check(np.array_equal(vtk_to_numpy(arrays[name]), np.float32(expected[name])), f"{frame_file}: {name} differs")
    check(arrays["id"].GetDataType() in (VTK_LONG, VTK_LONG_LONG) and arrays["id"].GetDataTypeSize() == 8,
          f"{frame_file}: id is {arrays['id'].GetDataTypeAsString()}, not a 64-bit integer")
    check(np.array_equal(vtk_to_numpy(arrays["id"]), np.array(expected["id"], dtype=np.int64)),
          f"{frame_file}: id differs")
print(f"{frame_file}: {n} points, arrays {sorted(arrays)}, time {times(frame)}")

# The index: one time step per frame file, at the frames' TimeValues.
index_file = os.path.join(directory, "particles.h5part")
index = H5PartReader(FileName=index_file)
check(times(index) == expected["index_times"], f"{index_file}: times {times(index)}, expected {expected['index_times']}")
for t in times(index):
    count = fetch(index, t).GetNumberOfPoints()
    check(count == expected["particles"], f"{index_file}: {count} points at time {t}")
print(f"{index_file}: time steps {times(index)}")

if failures:
    print(f"paraview h5part: {len(failures)} checks failed")
    sys.exit(1)
print("paraview h5part: all checks passed")
