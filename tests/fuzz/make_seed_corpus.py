#!/usr/bin/env python3
"""Writes the seed corpus of tests/fuzz/corpus/ (see docs/fuzzing.md).

Small valid files of each format plus edge cases that parse or fail near the
limits (truncation, huge counts, non-unit quaternions, CRLF, headers). Crash
inputs found by fuzzing are NOT made here: they are checked in as found
(corpus/<target>/crash-*), so rerunning this script keeps them.
Usage: tests/fuzz/make_seed_corpus.py  (from anywhere; needs only Python 3).
"""
import os
import sqlite3
import struct
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "corpus")
SEP = b"@@ODOMCAL-FILE@@"  # tests/fuzz/split_input.h


def put(target, name, data):
    folder = os.path.join(ROOT, target)
    os.makedirs(folder, exist_ok=True)
    if isinstance(data, str):
        data = data.encode()
    with open(os.path.join(folder, "seed-" + name), "wb") as f:
        f.write(data)


# --- COLMAP binary model (adapters/colmap_model.h) ------------------------
NUM_PARAMS = [3, 4, 4, 5, 8, 8, 12, 5, 4, 5, 12]
NONE = 2**64 - 1


def cameras_bin(cams):
    out = struct.pack("<Q", len(cams))
    for cam_id, model, w, h, params in cams:
        out += struct.pack("<IiQQ", cam_id, model, w, h)
        out += struct.pack("<%dd" % len(params), *params)
    return out


def images_bin(images):
    out = struct.pack("<Q", len(images))
    for image_id, q, t, cam_id, name, points in images:
        out += struct.pack("<I4d3dI", image_id, *q, *t, cam_id)
        out += name + b"\0"
        out += struct.pack("<Q", len(points))
        for x, y, p3d in points:
            out += struct.pack("<ddQ", x, y, p3d)
    return out


def points_bin(points):
    out = struct.pack("<Q", len(points))
    for pid, xyz, rgb, err, track in points:
        out += struct.pack("<Q3d3Bd", pid, *xyz, *rgb, err)
        out += struct.pack("<Q", len(track))
        for image_id, idx in track:
            out += struct.pack("<II", image_id, idx)
    return out


Q_ASYM = (0.9238795325112867, 0.0, 0.3826834323650898, 0.0)
CAMS = [(1, 1, 640, 480, [500.0, 510.0, 320.0, 240.0])]
IMAGES = [
    (1, (1.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 1, b"cam0/000001.png",
     [(10.5, 20.25, 0), (30.0, 40.0, NONE)]),
    (2, Q_ASYM, (0.1, -0.2, 0.3), 1, b"cam0/000002.png", [(11.0, 21.0, 0)]),
]
POINTS = [(0, (1.0, 2.0, 3.0), (255, 128, 0), 0.5, [(1, 0), (2, 0)])]


def model_bin(cams, images, points):
    return cameras_bin(cams) + SEP + images_bin(images) + SEP + points_bin(points)


T = "colmap_binary_model"
put(T, "two_images", model_bin(CAMS, IMAGES, POINTS))
put(T, "empty_model", model_bin([], [], []))
put(T, "every_camera_model", model_bin(
    [(i + 1, i, 100, 80, [float(j + 1) for j in range(n)])
     for i, n in enumerate(NUM_PARAMS)], [], []))
put(T, "huge_count", struct.pack("<Q", 2**62) + SEP + images_bin([]) + SEP +
    points_bin([]))
put(T, "truncated_image", model_bin(CAMS, IMAGES, POINTS)[:150])
put(T, "no_name_terminator", cameras_bin(CAMS) + SEP + struct.pack(
    "<QI4d3dI", 1, 1, 1, 0, 0, 0, 0, 0, 0, 1) + b"abc" + SEP + points_bin([]))
put(T, "non_unit_quaternion", model_bin(
    CAMS, [(1, (2.0, 0.0, 0.0, 0.0), (0, 0, 0), 1, b"a.png", [])], []))
put(T, "track_to_missing_point2d", model_bin(
    CAMS, IMAGES[:1], [(0, (0, 0, 0), (0, 0, 0), -1.0, [(1, 7)])]))

# --- COLMAP text model ------------------------------------------------------
CAMERAS_TXT = ("# Camera list with one line of data per camera:\n"
               "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
               "# Number of cameras: 2\n"
               "1 PINHOLE 640 480 500 510 320 240\n"
               "2 SIMPLE_RADIAL 320 240 300 160 120 -0.01\n")
IMAGES_TXT = ("# Image list with two lines of data per image:\n"
              "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
              "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
              "1 1 0 0 0 0 0 0 1 cam0/000001.png\n"
              "10.5 20.25 0 30 40 -1\n"
              "2 0.92387953251128674 0 0.38268343236508978 0 0.1 -0.2 0.3 2 "
              "cam0/000002.png\n"
              "\n")
POINTS_TXT = ("# 3D point list with one line of data per point:\n"
              "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as "
              "(IMAGE_ID, POINT2D_IDX)\n"
              "0 1 2 3 255 128 0 0.5 1 0\n")


def model_txt(c, i, p):
    return c.encode() + SEP + i.encode() + SEP + p.encode()


T = "colmap_text_model"
put(T, "two_images", model_txt(CAMERAS_TXT, IMAGES_TXT, POINTS_TXT))
put(T, "empty_model", model_txt("# none\n", "", ""))
put(T, "every_camera_model", model_txt("".join(
    "%d %s 100 80 %s\n" % (i + 1, name, " ".join(str(j + 1) for j in range(n)))
    for i, (name, n) in enumerate(zip(
        ["SIMPLE_PINHOLE", "PINHOLE", "SIMPLE_RADIAL", "RADIAL", "OPENCV",
         "OPENCV_FISHEYE", "FULL_OPENCV", "FOV", "SIMPLE_RADIAL_FISHEYE",
         "RADIAL_FISHEYE", "THIN_PRISM_FISHEYE"], NUM_PARAMS))), "", ""))
put(T, "crlf", model_txt(CAMERAS_TXT.replace("\n", "\r\n"),
                         IMAGES_TXT.replace("\n", "\r\n"),
                         POINTS_TXT.replace("\n", "\r\n")))
put(T, "image_without_points_line", model_txt(
    CAMERAS_TXT, "1 1 0 0 0 0 0 0 1 a.png", ""))
put(T, "huge_numbers", model_txt(
    "4294967295 PINHOLE 18446744073709551615 1 1e308 1 1 1\n",
    "4294967296 1 0 0 0 nan 0 0 1 a.png\n\n",
    "9223372036854775807 1 2 3 256 0 0 -1\n"))

# --- COLMAP database (adapters/colmap_database.h) ---------------------------
SCHEMA = (
    "CREATE TABLE cameras (camera_id INTEGER PRIMARY KEY AUTOINCREMENT NOT "
    "NULL, model INTEGER NOT NULL, width INTEGER NOT NULL, height INTEGER NOT "
    "NULL, params BLOB, prior_focal_length INTEGER NOT NULL);"
    "CREATE TABLE images (image_id INTEGER PRIMARY KEY AUTOINCREMENT NOT NULL, "
    "name TEXT NOT NULL UNIQUE, camera_id INTEGER NOT NULL, prior_qw REAL, "
    "prior_qx REAL, prior_qy REAL, prior_qz REAL, prior_tx REAL, prior_ty "
    "REAL, prior_tz REAL);")
LOOSE_SCHEMA = (  # no constraints, so that bad values can be stored
    "CREATE TABLE cameras (camera_id, model, width, height, params, "
    "prior_focal_length); CREATE TABLE images (image_id, name, camera_id);")


def database(schema, cameras, images):
    fd, path = tempfile.mkstemp(suffix=".db")
    os.close(fd)
    os.remove(path)
    db = sqlite3.connect(path)
    db.execute("PRAGMA page_size = 512")  # the smallest pages: small seeds
    db.executescript(schema)
    if cameras:
        db.executemany("INSERT INTO cameras VALUES (?, ?, ?, ?, ?, ?)", cameras)
    if images:
        db.executemany("INSERT INTO images (image_id, name, camera_id) "
                       "VALUES (?, ?, ?)", images)
    db.commit()
    db.execute("VACUUM")
    db.close()
    with open(path, "rb") as f:
        data = f.read()
    os.remove(path)
    return data


def params(*values):
    return struct.pack("<%dd" % len(values), *values)


T = "colmap_database"
put(T, "two_images.db", database(
    SCHEMA, [(1, 1, 640, 480, params(500, 510, 320, 240), 1),
             (2, 0, 320, 240, params(300, 160, 120), 0)],
    [(1, "cam0/000002.png", 1), (2, "cam0/000001.png", 2)]))
put(T, "empty_tables.db", database(SCHEMA, [], []))
put(T, "no_tables.db", database("CREATE TABLE other (x);", [], []))
put(T, "odd_values.db", database(
    LOOSE_SCHEMA,
    [(None, 99, -1, "wide", b"\x00" * 7, None),
     (4294967296, 1, 1, 1, "not a blob", 1),
     (3, 0, 1, 1, params(float("nan"), 1, 1), 2)],
    [(None, None, None), (-1, b"\xff\xfe", 1.5), (7, "a.png", 4294967295)]))
put(T, "text_everywhere.db", database(
    LOOSE_SCHEMA, [("1", "1", "640", "480", params(1, 2, 3, 4), "1")],
    [("1", "a.png", "1")]))

# --- TUM trajectory (adapters/trajectory_io.h) ------------------------------
T = "tum_trajectory"
put(T, "three_poses.tum",
    "# timestamp tx ty tz qx qy qz qw\n"
    "1403636579.763555584 0 0 0 0 0 0 1\n"
    "1403636579.813555456 0.1 0.01 0 0 0 0.0499792 0.9987503\n"
    "1403636579.863555584 0.2 0.03 0 0 0 0.0998334 0.9950042\n")
put(T, "commas_crlf.tum", "0,1,2,3,0,0,0,1\r\n0.5,1,2,3,0,0,0,1\r\n")
put(T, "nanoseconds.tum",
    "1403636579763555584 0 0 0 0 0 0 1\n1403636579813555456 0 0 0 0 0 0 1\n")
put(T, "bad_lines.tum",
    "1 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n0.5 0 0 0 0 0 0 1\n"
    "2 nan 0 0 0 0 0 1\n3 0 0 0 0 0 0 2\n4 0 0 0 0 0 0\n1e9 0 0 0 0 0 0 1\n")
put(T, "extremes.tum",
    "-9223372036.854775808 1e308 -1e308 0 0 0 0 1\n"
    "99999999999 0 0 0 0.7071067811865476 0 0 0.7071067811865476\n")

# --- Odometry CSV ------------------------------------------------------------
T = "odometry_csv"
put(T, "with_header.csv",
    "timestamp,x,y,yaw\n0.0,0,0,0\n0.1,0.05,0.001,0.01\n0.2,0.1,0.004,0.02\n")
put(T, "no_header_ns.csv",
    "# stamps in ns\n1403636579763555584,0,0,0\n1403636579813555456,1,2,-3.14\n")
put(T, "crlf_blanks.csv", "t,x,y,yaw\r\n\r\n  1 , 2 , 3 , 4 \r\n#c\r\n2,3,4,5\r\n")
put(T, "bad_lines.csv",
    "t,x,y\n1,0,0,0\n1,0,0,0\n0,0,0,0\n2,,0,0\n3,0,0,inf\n4,0,0,0,0\n-,1,2,3\n")
put(T, "tum_line_for_auto", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n")

# --- Image timestamps --------------------------------------------------------
T = "image_timestamps"
put(T, "with_header.csv",
    "image_name,timestamp\ncam0/000001.png,0.0\ncam0/000002.png,0.05\n"
    "cam1/000001.png,1403636579.763555584\n")
put(T, "names_only",
    "1403636579763555584.png\ncam0/1403636579.763555.png\ncam0/000123.png\n"
    "x.png\n1.5\n.png\n99999999999999999999.png\n")
put(T, "crlf_comments.csv", "# c\r\na.png , 1\r\n\r\nb.png,2.5\r\n")
put(T, "bad_lines.csv",
    "a.png,1\na.png,2\n,3\nb.png\nc.png,1e9\nd.png,nan\ne.png,1,2\n")
