"""Reading the particle frames that `pbf run` / pbf.run write (frame_NNNNN.ply).

The format (src/io/ply.cpp): binary little-endian PLY, one vertex per
particle, sorted by id, with the properties x y z vx vy vz density (float)
and id (uint), 32 bytes per particle. read_ply maps any binary
little-endian PLY vertex element with such scalar properties to numpy.
"""

import os

import numpy as np

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}


def read_ply(path):
    """The vertices of a binary little-endian PLY file as a numpy structured
    array (fields named as the file's properties: x, y, z, vx, vy, vz,
    density, id for pbf's frames). Raises ValueError naming the file if it
    is not such a file."""
    path = os.fspath(path)
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise ValueError(f"{path}: not a PLY file")
    fields, count, in_vertex, binary = [], None, False, False
    for line in data[:end].decode("ascii").splitlines()[1:]:
        words = line.split()
        if not words or words[0] == "comment":
            continue
        if words[0] == "format":
            binary = words[1] == "binary_little_endian"
        elif words[0] == "element":
            in_vertex = words[1] == "vertex"
            if in_vertex:
                count = int(words[2])
            elif count is not None:
                break  # elements after the vertices are not read
            else:
                raise ValueError(f"{path}: elements before 'vertex' are not supported")
        elif words[0] == "property" and in_vertex:
            if words[1] == "list" or words[1] not in _PLY_TYPES:
                raise ValueError(f"{path}: unsupported vertex property '{line}'")
            fields.append((words[2], _PLY_TYPES[words[1]]))
    if not binary:
        raise ValueError(f"{path}: only binary_little_endian PLY is supported")
    if count is None:
        raise ValueError(f"{path}: no vertex element")
    dtype = np.dtype(fields)
    start = end + len(b"end_header\n")
    if len(data) - start < count * dtype.itemsize:
        raise ValueError(f"{path}: truncated: {count} vertices need "
                         f"{count * dtype.itemsize} bytes, the file has {len(data) - start}")
    return np.frombuffer(data, dtype=dtype, count=count, offset=start)
