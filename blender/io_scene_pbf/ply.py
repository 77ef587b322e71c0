"""Binary little-endian PLY files as pbf writes them, read with numpy.

Particle frames (`frame_NNNNN.ply`: vertex x y z vx vy vz density id) and
surface meshes (`surface_NNNNN.ply`: vertex x y z [nx ny nz], faces as
`list uchar uint vertex_indices` triangles). Blender's own PLY importer drops
every property but the position and reads one file into a new object;
numpy reads a 100k-vertex frame in milliseconds.
"""

import numpy as np

_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}


class PlyError(ValueError):
    """A file that is not a binary little-endian PLY this reader understands."""


class Ply:
    """`vertex`: structured numpy array of the vertex properties;
    `triangles`: (F, 3) uint32 vertex indices, or None without faces."""

    def __init__(self, vertex, triangles):
        self.vertex = vertex
        self.triangles = triangles

    def has(self, *names):
        return all(n in self.vertex.dtype.names for n in names)

    def vectors(self, a, b, c):
        """(N, 3) float32 array of three vertex properties."""
        v = self.vertex
        return np.stack([v[a], v[b], v[c]], axis=1).astype(np.float32, copy=False)


def _parse_header(path, f):
    if f.readline().strip() != b"ply":
        raise PlyError(f"{path}: not a PLY file (no 'ply' magic)")
    elements = []  # (name, count, [(name, dtype)] or ("list", count type, item type, name))
    fmt = None
    while True:
        line = f.readline()
        if not line:
            raise PlyError(f"{path}: truncated header (no end_header)")
        words = line.decode("ascii", "replace").split()
        if not words or words[0] in ("comment", "obj_info"):
            continue
        if words[0] == "end_header":
            break
        if words[0] == "format":
            fmt = words[1] if len(words) > 1 else ""
        elif words[0] == "element":
            if len(words) != 3 or not words[2].isdigit():
                raise PlyError(f"{path}: bad element line '{line.strip().decode()}'")
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            if not elements:
                raise PlyError(f"{path}: property before any element")
            if words[1] == "list":
                if len(words) != 5 or words[2] not in _TYPES or words[3] not in _TYPES:
                    raise PlyError(f"{path}: bad list property '{line.strip().decode()}'")
                elements[-1][2].append(("list", _TYPES[words[2]], _TYPES[words[3]], words[4]))
            else:
                if len(words) != 3 or words[1] not in _TYPES:
                    raise PlyError(f"{path}: unsupported property '{line.strip().decode()}'")
                elements[-1][2].append((words[2], _TYPES[words[1]]))
    if fmt != "binary_little_endian":
        raise PlyError(f"{path}: format {fmt}: only binary_little_endian PLY is read")
    return elements


def read_ply(path):
    """Reads `path`; raises PlyError naming the file for anything else."""
    with open(path, "rb") as f:
        elements = _parse_header(path, f)
        data = f.read()
    offset = 0
    vertex = None
    triangles = None
    for name, count, props in elements:
        if any(p[0] == "list" for p in props):
            # Only triangles: a fixed record of (count, 3 indices) per face.
            if len(props) != 1:
                raise PlyError(f"{path}: element {name}: only one list property is read")
            _, count_type, item_type, _ = props[0]
            dtype = np.dtype([("n", count_type), ("i", item_type, 3)])
        else:
            dtype = np.dtype(props)
        size = dtype.itemsize * count
        if offset + size > len(data):
            raise PlyError(f"{path}: file is shorter than its {name} count ({count}) says")
        records = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
        offset += size
        if name == "vertex":
            vertex = records
        elif name == "face":
            if count and not np.all(records["n"] == 3):
                raise PlyError(f"{path}: faces other than triangles")
            triangles = records["i"].astype(np.uint32, copy=False)
    if vertex is None or not all(c in vertex.dtype.names for c in ("x", "y", "z")):
        raise PlyError(f"{path}: no vertex element with x, y, z")
    if triangles is not None and triangles.size and triangles.max() >= len(vertex):
        raise PlyError(f"{path}: a face refers to a vertex that does not exist")
    return Ply(vertex, triangles)
