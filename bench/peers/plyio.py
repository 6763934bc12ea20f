"""The PLY reading and writing the peer benchmark's Python scripts share.

read_vertices(path) -> (numpy structured array of the vertex element, header)
    ASCII or binary little-endian; the vertex element must come first (it does
    in every file the benchmark sees: recon's, PCL's, the C++ peers').
    header["elements"] maps each element name to its count.
positions(path) -> (n, 3) float64 array of the vertices' x y z.
write_points(path, positions, normals): binary little-endian, double
    x y z nx ny nz, the layout of recon's own files.
"""

import numpy as np

_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "<i2", "int16": "<i2", "ushort": "<u2", "uint16": "<u2",
    "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
    "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8",
}


def read_vertices(path):
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, elements, order, props = None, {}, [], {}
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            words = line.decode("ascii", "replace").split()
            if not words:
                continue
            if words[0] == "format":
                fmt = words[1]
            elif words[0] == "element":
                elements[words[1]] = int(words[2])
                order.append(words[1])
                props[words[1]] = []
            elif words[0] == "property":
                props[order[-1]].append(words[1:])
            elif words[0] == "end_header":
                break
        if not order or order[0] != "vertex":
            raise ValueError(f"{path}: the vertex element must come first")
        if any(p[0] == "list" for p in props["vertex"]):
            raise ValueError(f"{path}: list property in the vertex element")
        dtype = np.dtype([(name, _TYPES[t]) for t, name in props["vertex"]])
        count = elements["vertex"]
        if fmt == "binary_little_endian":
            data = np.frombuffer(f.read(count * dtype.itemsize), dtype=dtype, count=count)
        elif fmt == "ascii":
            rows = np.loadtxt(f, max_rows=count, ndmin=2)
            data = np.zeros(count, dtype=dtype)
            for i, name in enumerate(dtype.names):
                data[name] = rows[:, i]
        else:
            raise ValueError(f"{path}: unsupported PLY format {fmt}")
    return data, {"format": fmt, "elements": elements}


def columns(data, *names):
    """An (n, len(names)) float64 array of the named vertex properties."""
    return np.stack([data[n].astype(np.float64) for n in names], axis=1)


def positions(path):
    data, _ = read_vertices(path)
    return columns(data, "x", "y", "z")


def write_points(path, positions, normals):
    n = len(positions)
    record = np.empty(n, dtype=[(c, "<f8") for c in ("x", "y", "z", "nx", "ny", "nz")])
    for i, c in enumerate("xyz"):
        record[c] = positions[:, i]
        record["n" + c] = normals[:, i]
    with open(path, "wb") as f:
        f.write(b"ply\nformat binary_little_endian 1.0\ncomment written by bench/peers\n")
        f.write(f"element vertex {n}\n".encode())
        for c in ("x", "y", "z", "nx", "ny", "nz"):
            f.write(f"property double {c}\n".encode())
        f.write(b"end_header\n")
        f.write(record.tobytes())
