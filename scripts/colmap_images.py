"""The camera centres of a COLMAP binary model's images.bin.

Layout (adapters/colmap_model.h): a uint64 count, then per image its id
(uint32), cam_from_world as a Hamilton quaternion (w, x, y, z) and a
translation (doubles), its camera id (uint32), its name (NUL-terminated) and
its 2D points (uint64 count, then x, y as doubles and a point id as int64
each). Pure Python, so that the benchmarks need no numpy.
"""
import struct


def rotation_matrix(q_wxyz):
    """Rows of the rotation matrix of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q_wxyz
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def camera_centres(images_bin):
    """Image name -> its camera centre in the model's frame, -R^T t."""
    centres = {}
    with open(images_bin, "rb") as f:
        (count,) = struct.unpack("<Q", f.read(8))
        for _ in range(count):
            f.read(4)
            q = struct.unpack("<4d", f.read(32))
            t = struct.unpack("<3d", f.read(24))
            f.read(4)
            name = b""
            while (c := f.read(1)) != b"\0":
                name += c
            (num_points,) = struct.unpack("<Q", f.read(8))
            f.read(24 * num_points)
            r = rotation_matrix(q)
            centres[name.decode()] = tuple(-sum(r[k][j] * t[k] for k in range(3))
                                           for j in range(3))
    return centres
