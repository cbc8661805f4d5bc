"""COLMAP's initial pairs of an `odomcal run` on a rendered scene, against the truth.

    python3 scripts/initial_pair_truth.py DATA WS

DATA: the `odomcal render` folder (ground_truth.json), WS: the run's workspace
(database.db, odometry_pairs.txt, logs/mapper_*.log). Prints, per mapper log,
how often it found no initial pair and the pair it started from, with the
true |t_z| of the direction of motion in each camera (COLMAP 3.8 starts only
from pairs whose estimated |t_z| < Mapper.init_max_forward_motion, 0.95), the
true baseline and the pair's verified inliers (two_view_geometries.rows);
then, for the matched pairs, how many pass that test by the truth. Pure
Python (no numpy).
"""
import glob
import json
import math
import os
import re
import sqlite3
import sys

from colmap_images import rotation_matrix

PAIR_ID_BASE = 2147483647  # COLMAP's pair_id = id1 * base + id2, id1 < id2


def true_forward_motion(poses, name_a, name_b):
    """|t_z| in camera a and b of the unit direction between their centres."""
    (rot_a, centre_a), (rot_b, centre_b) = poses[name_a], poses[name_b]
    d = [centre_b[k] - centre_a[k] for k in range(3)]
    length = math.sqrt(sum(v * v for v in d))
    d = [v / length for v in d]
    z_a = abs(sum(rot_a[k][2] * d[k] for k in range(3)))
    z_b = abs(sum(rot_b[k][2] * d[k] for k in range(3)))
    return z_a, z_b, length


def main(data, ws):
    truth = json.load(open(os.path.join(data, "ground_truth.json")))
    poses = {image["name"]: (rotation_matrix(image["world_from_cam"]["quaternion_wxyz"]),
                             image["world_from_cam"]["translation_m"])
             for image in truth["images"]}
    db = sqlite3.connect("file:%s?mode=ro" % os.path.join(ws, "database.db"), uri=True)
    names = dict(db.execute("SELECT image_id, name FROM images"))
    inliers = {}
    for pair_id, rows in db.execute("SELECT pair_id, rows FROM two_view_geometries"):
        inliers[(pair_id // PAIR_ID_BASE, pair_id % PAIR_ID_BASE)] = rows
    for log in sorted(glob.glob(os.path.join(ws, "logs", "mapper_*.log"))):
        text = open(log).read()
        print("%s: 'No good initial image pair found' x%d" %
              (os.path.basename(log), text.count("No good initial image pair found")))
        for match in re.finditer(r"Initializing with image pair #(\d+) and #(\d+)", text):
            i, j = int(match.group(1)), int(match.group(2))
            z_a, z_b, length = true_forward_motion(poses, names[i], names[j])
            print("  initialised from %s and %s: true |t_z| %.3f / %.3f, baseline %.2f m, "
                  "%s verified inliers" % (names[i], names[j], z_a, z_b, length,
                                           inliers.get((min(i, j), max(i, j)))))
    pairs = [line.split() for line in open(os.path.join(ws, "odometry_pairs.txt")) if line.strip()]
    passing = sum(1 for a, b in pairs if min(true_forward_motion(poses, a, b)[:2]) < 0.95)
    print("odometry pairs: %d, passing |t_z| < 0.95 by the truth in either camera: %d" %
          (len(pairs), passing))


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])
