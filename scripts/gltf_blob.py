# One binary buffer of a glTF being written by a fixture script (meshopt-fixture-source.py,
# instancing-fixture-source.py): each added list of rows gets a buffer view and an accessor.
import struct


class Blob:
    def __init__(self):
        self.data = b''
        self.views = []
        self.accessors = []

    def add(self, fmt, rows, typ, ct, target=None, minmax=False):
        """Rows packed little-endian as `fmt` each, 4-byte aligned; returns the accessor index."""
        while len(self.data) % 4:
            self.data += b'\0'
        data = b''.join(struct.pack('<' + fmt, *(r if isinstance(r, tuple) else (r,))) for r in rows)
        v = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(data)}
        if target:
            v["target"] = target
        self.views.append(v)
        self.data += data
        a = {"bufferView": len(self.views) - 1, "componentType": ct, "count": len(rows), "type": typ}
        if minmax:
            cols = list(zip(*rows))
            a["min"] = [min(c) for c in cols]
            a["max"] = [max(c) for c in cols]
        self.accessors.append(a)
        return len(self.accessors) - 1


def sphere_triangles(rings, segs):
    """The triangles of a (rings + 1) × (segs + 1) latitude-longitude vertex grid, the poles'
    degenerate ones left out."""
    idx = []
    for i in range(rings):
        for j in range(segs):
            a = i * (segs + 1) + j
            b = a + segs + 1
            if i != 0:
                idx += [a, b, a + 1]
            if i != rings - 1:
                idx += [a + 1, b, b + 1]
    return idx
