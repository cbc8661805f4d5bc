"""Unit tests of the Python module odomcal (python/odomcal_module.cc).

A noise-free planar drive made here with numpy, with a known odom_from_cam
and metric scale: the module must recover them from arrays and from files,
and reject bad keywords and arrays with the CLI's one-line messages.
Run by ctest with Debian's /usr/bin/python3 and PYTHONPATH=<build>/python.
"""
import importlib.util
import math
import os
import pathlib
import tempfile
import struct
import unittest
import zlib

import numpy as np

import odomcal

ODOMETRY_RATE_HZ = 50.0
CAMERA_EVERY = 5  # a camera pose every 5th odometry sample: 10 Hz
METRIC_SCALE = 0.37  # metres per reconstruction unit


def quaternion_xyzw_to_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def matrix_to_quaternion_xyzw(r):
    # Shepperd's method, stable for every rotation.
    t = np.trace(r)
    if t > 0:
        s = 2 * math.sqrt(t + 1)
        q = [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s,
             (r[1, 0] - r[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2 * math.sqrt(1 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0] * 4
        q[i] = s / 4
        q[j] = (r[j, i] + r[i, j]) / s
        q[k] = (r[k, i] + r[i, k]) / s
        q[3] = (r[k, j] - r[j, k]) / s
    return np.array(q)


def yaw_matrix(yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def with_value(array, row, col, value):
    changed = array.copy()
    changed[row, col] = value
    return changed


def rotation_error_deg(r_a, r_b):
    e = r_a.T @ r_b
    sine = np.linalg.norm([e[2, 1] - e[1, 2], e[0, 2] - e[2, 0], e[1, 0] - e[0, 1]]) / 2
    return math.degrees(math.atan2(sine, (np.trace(e) - 1) / 2))


# The truth: camera looking forward (z_cam = x_odom, x_cam = -y_odom), tilted
# down by 10 deg, 25 cm ahead, 5 cm left, 40 cm up.
ODOM_FROM_CAM_R = np.array([[0, 0, 1], [-1, 0, 0], [0, -1, 0]]) @ \
    np.array([[1, 0, 0], [0, math.cos(0.17), -math.sin(0.17)],
              [0, math.sin(0.17), math.cos(0.17)]])
ODOM_FROM_CAM_T = np.array([0.25, 0.05, 0.40])
# The SfM frame: rotated, shifted, in reconstruction units.
SFM_FROM_ORIGIN_R = quaternion_xyzw_to_matrix(np.array([0.1, -0.3, 0.2, 0.9]) /
                                              np.linalg.norm([0.1, -0.3, 0.2, 0.9]))
SFM_FROM_ORIGIN_T = np.array([1.0, -2.0, 0.5])


def simulated_drive(start_s=100.0, duration_s=40.0, turning=True):
    """Odometry (M, 4) [t, x, y, yaw] and camera poses (N, 8) TUM, noise-free."""
    n = int(duration_s * ODOMETRY_RATE_HZ) + 1
    t = start_s + np.arange(n) / ODOMETRY_RATE_HZ
    tau = t - start_s
    # Turns both ways at varying rates and speeds: every quantity observable.
    yaw_rate = 0.6 * np.sin(0.35 * tau) + 0.25 * np.sin(1.1 * tau + 0.5)
    if not turning:
        yaw_rate = 0.0 * tau
    speed = 0.3 + 0.15 * np.sin(0.2 * tau)
    yaw = np.concatenate([[0.0], np.cumsum(yaw_rate[:-1]) / ODOMETRY_RATE_HZ])
    yaw = np.arctan2(np.sin(yaw), np.cos(yaw))
    x = np.concatenate([[0.0], np.cumsum(speed[:-1] * np.cos(yaw[:-1])) / ODOMETRY_RATE_HZ])
    y = np.concatenate([[0.0], np.cumsum(speed[:-1] * np.sin(yaw[:-1])) / ODOMETRY_RATE_HZ])
    odometry = np.column_stack([t, x, y, yaw])
    camera = []
    for i in range(0, n, CAMERA_EVERY):
        r_origin_from_odom = yaw_matrix(yaw[i])
        p_origin_from_odom = np.array([x[i], y[i], 0.0])
        r_origin_from_cam = r_origin_from_odom @ ODOM_FROM_CAM_R
        p_origin_from_cam = r_origin_from_odom @ ODOM_FROM_CAM_T + p_origin_from_odom
        r = SFM_FROM_ORIGIN_R @ r_origin_from_cam
        p = SFM_FROM_ORIGIN_R @ p_origin_from_cam / METRIC_SCALE + SFM_FROM_ORIGIN_T
        camera.append(np.concatenate([[t[i]], p, matrix_to_quaternion_xyzw(r)]))
    return np.array(camera), odometry


def write_colmap_project(folder, camera, odometry):
    """A COLMAP text model (sparse/0) of the camera poses, image_timestamps.csv and
    odometry.csv under folder; returns (model root, odometry path, timestamps path)."""
    model = os.path.join(folder, "sparse", "0")
    os.makedirs(model)
    with open(os.path.join(model, "cameras.txt"), "w") as f:
        f.write("1 PINHOLE 320 240 250 250 160 120\n")
    with open(os.path.join(model, "images.txt"), "w") as f, \
            open(os.path.join(folder, "image_timestamps.csv"), "w") as stamps:
        stamps.write("image_name,timestamp\n")
        for i, row in enumerate(camera):
            r_world_from_cam = quaternion_xyzw_to_matrix(row[4:8])
            r = r_world_from_cam.T  # cam_from_world, as COLMAP stores it
            t = -r @ row[1:4]
            x, y, z, w = matrix_to_quaternion_xyzw(r)
            name = "frame%04d.png" % i
            f.write("%d %.17g %.17g %.17g %.17g %.17g %.17g %.17g 1 %s\n\n" %
                    (i + 1, w, x, y, z, t[0], t[1], t[2], name))
            stamps.write("%s,%.9f\n" % (name, row[0]))
    open(os.path.join(model, "points3D.txt"), "w").close()
    odometry_path = os.path.join(folder, "odometry.csv")
    np.savetxt(odometry_path, odometry, fmt="%.17g", delimiter=",")
    return (os.path.join(folder, "sparse"), odometry_path,
            os.path.join(folder, "image_timestamps.csv"))


class CalibrateTest(unittest.TestCase):
    def assert_recovered(self, result):
        self.assertEqual(result["status"], "success", result["message"])
        self.assertEqual(result["schema"], "odomcal.calibration")
        transform = np.array(result["odom_from_cam"]["matrix"])
        self.assertLess(rotation_error_deg(transform[:3, :3], ODOM_FROM_CAM_R), 1e-6)
        # z is unobservable under planar motion: held at fixed_translation_z_m.
        translation = np.array(result["odom_from_cam"]["translation_m"])
        self.assertLess(np.max(np.abs(translation - ODOM_FROM_CAM_T)), 1e-6)
        self.assertAlmostEqual(result["metric_scale"], METRIC_SCALE, delta=1e-9)

    def test_arrays_recover_extrinsic_and_scale(self):
        camera, odometry = simulated_drive()
        result = odomcal.calibrate(camera_poses=camera, odometry=odometry,
                                   fixed_translation_z_m=0.40)
        self.assert_recovered(result)
        self.assertEqual(result["inputs"]["camera_poses"],
                         ["camera_poses (numpy array, %d x 8)" % len(camera)])
        self.assertEqual(result["fixed"]["translation_z_m"], 0.40)

    def test_nanosecond_times_and_keyword_flags(self):
        camera, odometry = simulated_drive(start_s=1.7e9)
        camera[:, 0] *= 1e9
        odometry[:, 0] *= 1e9
        result = odomcal.calibrate(camera_poses=camera, odometry=odometry,
                                   camera_time_unit="ns", odometry_time_unit="ns",
                                   fixed_translation_z_m=0.40, no_refine=False,
                                   ransac="off", method="alsp")
        self.assert_recovered(result)
        self.assertEqual(result["inputs"]["camera_time_unit"], "ns")
        self.assertFalse(result["options"]["ransac"])

    def test_files_recover_extrinsic_and_scale(self):
        camera, odometry = simulated_drive()
        with tempfile.TemporaryDirectory() as folder:
            camera_path = os.path.join(folder, "camera.txt")
            odometry_path = os.path.join(folder, "odometry.csv")
            np.savetxt(camera_path, camera, fmt="%.17g")
            np.savetxt(odometry_path, odometry, fmt="%.17g", delimiter=",")
            result = odomcal.calibrate(camera_poses=camera_path, odometry=odometry_path,
                                       fixed_translation_z_m=0.40)
        self.assert_recovered(result)
        self.assertEqual(result["inputs"]["camera_poses"], [camera_path])
        self.assertEqual(result["inputs"]["odometry"], odometry_path)

    def test_dict_of_cameras_calibrates_each_and_their_pair(self):
        camera, odometry = simulated_drive()
        straight, _ = simulated_drive(turning=False)
        result = odomcal.calibrate(camera_poses={"front": camera, "copy": camera.copy(),
                                                 "still": straight[:3]},
                                   odometry=odometry, fixed_translation_z_m=0.40,
                                   reference_camera="copy")
        self.assertEqual(result["reference_camera"], "copy")
        self.assert_recovered(result)
        names = [camera["name"] for camera in result["cameras"]]
        self.assertEqual(names, ["front", "copy", "still"])
        self.assertEqual(result["cameras"][0]["status"], "success")
        self.assertNotEqual(result["cameras"][2]["status"], "success")
        self.assertEqual(len(result["camera_pairs"]), 1)
        pair = np.array(result["camera_pairs"][0]["camb_from_cama"]["matrix"])
        self.assertLess(np.max(np.abs(pair - np.eye(4))), 1e-6)
        with self.assertRaises(ValueError) as raised:
            odomcal.calibrate(camera_poses={"front": camera}, odometry=odometry,
                              reference_camera="rear")
        self.assertIn("reference_camera", str(raised.exception))

    def test_straight_drive_is_not_calibrated(self):
        # Not an error: the result says why (the CLI's exit code 3).
        camera, odometry = simulated_drive(turning=False)
        result = odomcal.calibrate(camera_poses=camera, odometry=odometry)
        self.assertEqual(result["status"], "unobservable", result["message"])
        self.assertIn("rotation", result["unobservable"])

    def test_unknown_keyword_names_the_nearest(self):
        camera, odometry = simulated_drive(duration_s=2)
        with self.assertRaises(TypeError) as raised:
            odomcal.calibrate(camera_poses=camera, odometry=odometry,
                              max_odometry_gap=0.5)
        self.assertEqual(str(raised.exception),
                         "unknown keyword max_odometry_gap (did you mean max_odometry_gap_s?)")

    def test_bad_values_raise_the_cli_message(self):
        camera, odometry = simulated_drive(duration_s=2)
        cases = [
            (dict(max_odometry_gap_s=-1), "max_odometry_gap_s must be finite and > 0, got -1"),
            (dict(ransac="maybe"), "ransac: maybe not in {on,off}"),
            (dict(ransac_seed=-3), "ransac_seed must be >= 0, got -3"),
            (dict(camera_time_offset_s=float("nan")),
             "camera_time_offset_s must be finite and within [-1e9, 1e9], got nan"),
            (dict(wheel_ticks_per_m=1000),
             "wheel_ticks_per_m: given, but the odometry is an array of poses "
             "(t, x, y, yaw), not wheel ticks; drop it"),
        ]
        for keywords, message in cases:
            with self.subTest(keywords=keywords):
                with self.assertRaises(ValueError) as raised:
                    odomcal.calibrate(camera_poses=camera, odometry=odometry, **keywords)
                self.assertEqual(str(raised.exception), message)
        with self.assertRaises(TypeError) as raised:
            odomcal.calibrate(camera_poses=camera, odometry=odometry, no_refine=1)
        self.assertEqual(str(raised.exception), "no_refine takes True or False, got 1")

    def test_bad_arrays_raise_one_line(self):
        camera, odometry = simulated_drive(duration_s=2)
        cases = [
            (dict(camera_poses=camera[:, :7], odometry=odometry),
             "camera_poses: expected an array of shape (N, 8) [t, tx, ty, tz, qx, qy, qz, qw], "
             "got (%d, 7)" % len(camera)),
            (dict(camera_poses=camera, odometry=odometry[:, :3]),
             "odometry: expected an array of shape (N, 4) [t, x, y, yaw] or "
             "(N, 8) [t, tx, ty, tz, qx, qy, qz, qw], got (%d, 3)" % len(odometry)),
            (dict(camera_poses=camera[0], odometry=odometry),
             "camera_poses: expected a 2-D array, got shape (8,)"),
            (dict(camera_poses=np.vstack([camera[:3], camera[1:2]]), odometry=odometry),
             "camera_poses row 3: time not increasing (100.100000000 s after "
             "100.200000000 s in row 2)"),
            (dict(camera_poses=camera[:0], odometry=odometry),
             "camera_poses: the array has no rows"),
            (dict(camera_poses=[], odometry=odometry), "camera_poses: the list is empty"),
            (dict(camera_poses=camera, odometry=with_value(odometry, 4, 3, np.nan)),
             "odometry row 4: column 'yaw' is not finite (NaN or Inf)"),
            (dict(camera_poses=camera, odometry=with_value(odometry, 7, 3, 45.0)),
             "odometry row 7: yaw jumps from %.6g to 45 rad, more than pi and not a wrap "
             "of a yaw kept in -pi..pi or 0..2 pi (yaw must be in radians)" % odometry[6, 3]),
            (dict(camera_poses=with_value(camera, 0, 0, 1.7e18), odometry=odometry),
             "camera_poses row 0: time 1.7e+18 s is beyond the int64 nanosecond range "
             "(about 292 years); check the time unit"),
            (dict(camera_poses=with_value(camera, 2, slice(4, 8), [0, 0, 0.3, 0.4]),
                  odometry=odometry),
             "camera_poses row 2: quaternion (qx qy qz qw) has norm 0.5, more than 0.01 "
             "away from 1"),
            (dict(camera_poses=camera, odometry="/nonexistent/odometry.csv"),
             "/nonexistent/odometry.csv: cannot open for reading: No such file or directory"),
        ]
        for arguments, message in cases:
            with self.subTest(message=message):
                with self.assertRaises(ValueError) as raised:
                    odomcal.calibrate(**arguments)
                self.assertEqual(str(raised.exception), message)
        type_cases = [
            (dict(camera_poses=camera.tolist(), odometry=odometry),
             "camera_poses[0]: expected a file path or a numpy array, got list"),
            (dict(camera_poses=camera.astype(str), odometry=odometry),
             "camera_poses: expected an array of real numbers, got dtype %s" %
             camera.astype(str).dtype),
            (dict(camera_poses=camera, odometry=odometry, ransac=["on"]),
             "ransac takes a number or a string, got list"),
        ]
        for arguments, message in type_cases:
            with self.subTest(message=message):
                with self.assertRaises(TypeError) as raised:
                    odomcal.calibrate(**arguments)
                self.assertEqual(str(raised.exception), message)

    def test_int64_nanosecond_pairs_recover_extrinsic_and_scale(self):
        camera, odometry = simulated_drive(start_s=0.0)
        start_ns = 1_700_000_000_123_456_789  # a Unix time in ns, as ROS stamps
        camera_ns = start_ns + np.round(camera[:, 0] * 1e9).astype(np.int64)
        odometry_ns = start_ns + np.round(odometry[:, 0] * 1e9).astype(np.int64)
        # The unit keywords apply to float time columns, not to int64 times.
        result = odomcal.calibrate(camera_poses=(camera_ns, camera[:, 1:]),
                                   odometry=(odometry_ns, odometry[:, 1:]),
                                   camera_time_unit="ms", fixed_translation_z_m=0.40)
        self.assert_recovered(result)
        self.assertEqual(result["inputs"]["camera_poses"],
                         ["camera_poses (numpy arrays, %d int64 ns times and %d x 7 values)"
                          % (len(camera), len(camera))])
        # A list of segments may hold pairs too.
        result = odomcal.calibrate(camera_poses=[(camera_ns, camera[:, 1:])],
                                   odometry=(odometry_ns, odometry[:, 1:]),
                                   fixed_translation_z_m=0.40)
        self.assert_recovered(result)

    def test_bad_nanosecond_pairs_raise_one_line(self):
        camera, odometry = simulated_drive(duration_s=2)
        t_ns = np.round(camera[:, 0] * 1e9).astype(np.int64)
        with self.assertRaises(TypeError) as raised:
            odomcal.calibrate(camera_poses=(camera[:, 0], camera[:, 1:]), odometry=odometry)
        self.assertEqual(str(raised.exception),
                         "camera_poses: the times of (times, values) must be signed integer "
                         "nanoseconds (int64), got dtype float64")
        cases = [
            ((t_ns[:-1], camera[:, 1:]),
             "camera_poses: %d times for %d rows of values" % (len(t_ns) - 1, len(t_ns))),
            ((t_ns, camera[:, 1:7]),
             "camera_poses: expected values of shape (N, 7) [tx, ty, tz, qx, qy, qz, qw] "
             "beside the times, got (%d, 6)" % len(t_ns)),
            ((t_ns[::-1].copy(), camera[:, 1:]),
             "camera_poses row 1: time not increasing (101.900000000 s after "
             "102.000000000 s in row 0)"),
        ]
        for pair, message in cases:
            with self.subTest(message=message):
                with self.assertRaises(ValueError) as raised:
                    odomcal.calibrate(camera_poses=pair, odometry=odometry)
                self.assertEqual(str(raised.exception), message)

    def test_version(self):
        self.assertRegex(odomcal.__version__, r"^\d+\.\d+\.\d+$")


class CalibrateProjectTest(unittest.TestCase):
    """odomcal.calibrate_project: `odomcal colmap` on a COLMAP text model."""

    def test_project_recovers_extrinsic_and_scale_with_the_options_echo(self):
        camera, odometry = simulated_drive()
        with tempfile.TemporaryDirectory() as folder:
            model, odometry_path, stamps = write_colmap_project(folder, camera, odometry)
            result = odomcal.calibrate_project(
                model_path=pathlib.Path(model), odometry=odometry_path,
                image_timestamps=stamps, fixed_translation_z_m=0.40,
                min_inconsistent_run_pairs=4, robust_loss="huber")
        self.assertEqual(result["status"], "success", result["message"])
        transform = np.array(result["odom_from_cam"]["matrix"])
        self.assertLess(rotation_error_deg(transform[:3, :3], ODOM_FROM_CAM_R), 1e-6)
        translation = np.array(result["odom_from_cam"]["translation_m"])
        self.assertLess(np.max(np.abs(translation - ODOM_FROM_CAM_T)), 1e-6)
        self.assertAlmostEqual(result["metric_scale"], METRIC_SCALE, delta=1e-9)
        self.assertEqual(result["inputs"]["command"], "odomcal colmap")
        self.assertEqual(result["inputs"]["model_path"], model)
        self.assertEqual(result["inputs"]["image_timestamps"], stamps)
        self.assertIsNone(result["inputs"]["database_path"])
        # The echo of every option, as `odomcal colmap` writes it.
        self.assertEqual(result["options"]["min_inconsistent_run_pairs"], 4)
        self.assertEqual(result["options"]["robust_loss"], "huber")
        self.assertIn("odom_yaw_sigma_deg", result["options"]["noise"])
        self.assertIn("max_scale_stddev_rel", result["options"])
        self.assertIn("keyframe_min_rotation_deg", result["inputs"])
        self.assertEqual(len(result["colmap"]["sub_models"]), 1)
        # A given z overrides the floor, which is then only checked.
        self.assertEqual(result["options"]["floor_plane"], "check")
        self.assertEqual(result["translation_z_source"], "given")

    def test_project_without_floor_points_holds_z_with_the_reason(self):
        camera, odometry = simulated_drive()
        with tempfile.TemporaryDirectory() as folder:
            model, odometry_path, stamps = write_colmap_project(folder, camera, odometry)
            result = odomcal.calibrate_project(
                model_path=model, odometry=odometry_path, image_timestamps=stamps,
                odometry_height_m=0.05)
        self.assertEqual(result["status"], "success", result["message"])
        self.assertEqual(result["options"]["floor_plane"], "estimate")
        self.assertEqual(result["options"]["odometry_height_m"], 0.05)
        self.assertEqual(result["translation_z_source"], "given")
        self.assertIn("translation_z", result["unobservable"])
        self.assertEqual(result["floor_plane"]["status"], "too_few_points")
        self.assertTrue(result["floor_plane"]["translation_z_held_reason"].startswith(
            "the floor is not seen: 0 points below the cameras"),
            result["floor_plane"]["translation_z_held_reason"])

    def test_project_joint_adjustment_keyword(self):
        # The model has poses but no points: the adjustment is asked for,
        # runs, says why it cannot adjust, and the two-step result stands.
        camera, odometry = simulated_drive()
        with tempfile.TemporaryDirectory() as folder:
            model, odometry_path, stamps = write_colmap_project(folder, camera, odometry)
            result = odomcal.calibrate_project(
                model_path=model, odometry=odometry_path, image_timestamps=stamps,
                fixed_translation_z_m=0.40, joint_adjustment="on")
            default = odomcal.calibrate_project(
                model_path=model, odometry=odometry_path, image_timestamps=stamps,
                fixed_translation_z_m=0.40)
            off = odomcal.calibrate_project(
                model_path=model, odometry=odometry_path, image_timestamps=stamps,
                fixed_translation_z_m=0.40, joint_adjustment="off")
        self.assertEqual(result["status"], "success", result["message"])
        self.assertEqual(result["options"]["joint_adjustment"], "on")
        self.assertEqual(result["joint_adjustment"]["status"], "invalid_input")
        self.assertEqual(result["joint_adjustment"]["message"],
                         "no point is seen in two images whose rays meet at "
                         "the minimum triangulation angle")
        self.assertIsNone(result["diagnostics"]["two_step"])
        self.assertEqual(result["odom_from_cam"], off["odom_from_cam"])
        self.assertIsNone(off["joint_adjustment"])
        self.assertEqual(off["options"]["joint_adjustment"], "off")
        # The default checks the two-step estimate; a check that cannot run
        # leaves it, with no warning.
        self.assertEqual(default["options"]["joint_adjustment"], "check")
        self.assertEqual(default["joint_adjustment"]["use"], "check")
        self.assertFalse(default["joint_adjustment"]["adopted"])
        self.assertEqual(default["odom_from_cam"], off["odom_from_cam"])
        self.assertEqual(default["warnings"], off["warnings"])

    def test_project_with_two_cameras_calibrates_each(self):
        # The same poses seen by two COLMAP cameras in two sub-folders: a
        # rig of two cameras, each calibrated from its own images.
        camera, odometry = simulated_drive()
        with tempfile.TemporaryDirectory() as folder:
            model, odometry_path, stamps = write_colmap_project(folder, camera, odometry)
            images_path = os.path.join(model, "0", "images.txt")
            with open(images_path) as f:
                lines = [line for line in f if line.strip()]
            with open(images_path, "w") as f, open(stamps, "w") as times:
                times.write("image_name,timestamp\n")
                for k, (sub_folder, camera_id) in enumerate((("front", 1), ("rear", 2))):
                    for i, line in enumerate(lines):
                        fields = line.split()
                        fields[0] = str(k * len(lines) + i + 1)
                        fields[8] = str(camera_id)
                        fields[9] = sub_folder + "/" + fields[9]
                        f.write(" ".join(fields) + "\n\n")
                        times.write("%s,%.9f\n" % (fields[9], camera[i, 0]))
            with open(os.path.join(model, "0", "cameras.txt"), "a") as f:
                f.write("2 PINHOLE 320 240 250 250 160 120\n")
            result = odomcal.calibrate_project(
                model_path=model, odometry=odometry_path, image_timestamps=stamps,
                fixed_translation_z_m=0.40, reference_camera="rear")
        self.assertEqual(result["reference_camera"], "rear")
        self.assertEqual([c["name"] for c in result["cameras"]], ["front", "rear"])
        for camera_result in result["cameras"]:
            self.assertEqual(camera_result["status"], "success", camera_result["reason"])
            transform = np.array(camera_result["odom_from_cam"]["matrix"])
            self.assertLess(rotation_error_deg(transform[:3, :3], ODOM_FROM_CAM_R), 1e-6)
        self.assertEqual(len(result["camera_pairs"]), 1)
        self.assertEqual(len(result["shared_scales"]), 1)
        self.assertFalse(result["shared_scales"][0]["disagree"])

    def test_project_errors_name_the_keyword(self):
        with tempfile.TemporaryDirectory() as folder:
            camera, odometry = simulated_drive(duration_s=2)
            model, odometry_path, _ = write_colmap_project(folder, camera, odometry)
            with self.assertRaises(ValueError) as raised:
                odomcal.calibrate_project("/nonexistent/sparse", odometry_path)
            self.assertEqual(str(raised.exception),
                             "model_path: Directory does not exist: /nonexistent/sparse")
            with self.assertRaises(TypeError) as raised:
                odomcal.calibrate_project(model, odometry_path, min_inconsistent_run_pair=2)
            self.assertEqual(str(raised.exception),
                             "unknown keyword min_inconsistent_run_pair "
                             "(did you mean min_inconsistent_run_pairs?)")
            with self.assertRaises(ValueError) as raised:
                odomcal.calibrate_project(model, odometry_path, min_inconsistent_run_pairs=0)
            self.assertEqual(str(raised.exception),
                             "min_inconsistent_run_pairs must be >= 1, got 0")


def tiny_png(width, height):
    """A grey RGB PNG, written with the standard library."""
    rows = b"".join(b"\x00" + b"\x80" * (3 * width) for _ in range(height))

    def chunk(kind, data):
        return (struct.pack(">I", len(data)) + kind + data +
                struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))

    return (b"\x89PNG\r\n\x1a\n" +
            chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))


def write_ros1_bag(path, camera, odometry):
    """The drive as a ROS 1 bag written by Debian's python3-rosbag: PNG
    CompressedImage at the camera times, CameraInfo, nav_msgs/Odometry."""
    import rosbag
    import rospy
    from nav_msgs.msg import Odometry
    from sensor_msgs.msg import CameraInfo, CompressedImage
    png = tiny_png(16, 12)
    with rosbag.Bag(path, "w") as bag:
        for row in camera:
            stamp = rospy.Time.from_sec(row[0])
            image = CompressedImage(format="png", data=png)
            image.header.stamp = stamp
            bag.write("/cam/image/compressed", image, stamp)
            info = CameraInfo(width=16, height=12, distortion_model="plumb_bob")
            info.header.stamp = stamp
            info.D = [0.0] * 5
            info.K = [20.0, 0, 7.5, 0, 20.0, 5.5, 0, 0, 1]
            bag.write("/cam/camera_info", info, stamp)
        for t, x, y, yaw in odometry:
            message = Odometry()
            message.header.stamp = rospy.Time.from_sec(t)
            message.pose.pose.position.x = x
            message.pose.pose.position.y = y
            message.pose.pose.orientation.z = math.sin(yaw / 2)
            message.pose.pose.orientation.w = math.cos(yaw / 2)
            bag.write("/odom", message, message.header.stamp)


@unittest.skipUnless(importlib.util.find_spec("rosbag"), "python3-rosbag missing")
class BagTest(unittest.TestCase):
    """odomcal.extract and reconstruct_and_calibrate(bag=...) on a bag of
    python3-rosbag's, without COLMAP."""

    def test_extract_writes_the_inputs(self):
        camera, odometry = simulated_drive(duration_s=10)
        with tempfile.TemporaryDirectory() as folder:
            bag = os.path.join(folder, "drive.bag")
            write_ros1_bag(bag, camera, odometry)
            out = os.path.join(folder, "inputs")
            result = odomcal.extract(bag, out)
            self.assertEqual(result["images"]["topic"], "/cam/image/compressed")
            self.assertEqual(result["images"]["used"], len(camera))
            self.assertEqual(result["odometry"]["used"], len(odometry))
            self.assertTrue(result["planar"])
            self.assertEqual(result["camera_model"], "PINHOLE")
            # ROS's pixel centre (0, 0) -> COLMAP's (0.5, 0.5).
            self.assertEqual(result["camera_params"], "20,20,8,6")
            self.assertEqual(len(os.listdir(result["image_path"])), len(camera))
            rows = np.loadtxt(result["odometry_path"], delimiter=",", skiprows=1)
            np.testing.assert_allclose(rows[:, 1:], odometry[:, 1:], atol=1e-9)
            with self.assertRaisesRegex(ValueError, "image_topic"):
                odomcal.extract(bag, os.path.join(folder, "again"),
                                image_topic="/no/such/topic")

    def test_run_from_a_bag_is_refused_before_colmap_on_a_straight_drive(self):
        camera, odometry = simulated_drive(duration_s=20, turning=False)
        with tempfile.TemporaryDirectory() as folder:
            bag = os.path.join(folder, "drive.bag")
            write_ros1_bag(bag, camera, odometry)
            result = odomcal.reconstruct_and_calibrate(
                bag=bag, workspace_path=os.path.join(folder, "work"),
                colmap_path="/nonexistent/colmap")
            self.assertEqual(result["status"], "unobservable", result["message"])
            self.assertEqual(result["inputs"]["bag"], bag)
            self.assertEqual(result["options"]["bag"]["bag_time"], "header")
            self.assertEqual(result["options"]["run"]["camera_params"], "20,20,8,6")
            with self.assertRaisesRegex(ValueError, "bag"):
                odomcal.reconstruct_and_calibrate(
                    folder, bag, os.path.join(folder, "w2"), bag=bag)


class ReconstructAndCalibrateTest(unittest.TestCase):
    """odomcal.reconstruct_and_calibrate without COLMAP: what happens before it runs."""

    def image_folder(self, folder, camera):
        images = os.path.join(folder, "images")
        os.makedirs(images)
        for row in camera:  # times from the names: seconds with a decimal point
            open(os.path.join(images, "%.6f.png" % row[0]), "w").close()
        return images

    def test_a_straight_drive_is_refused_before_colmap(self):
        camera, odometry = simulated_drive(turning=False)
        steps = []
        with tempfile.TemporaryDirectory() as folder:
            images = self.image_folder(folder, camera)
            odometry_path = os.path.join(folder, "odometry.csv")
            np.savetxt(odometry_path, odometry, fmt="%.17g", delimiter=",")
            workspace = os.path.join(folder, "work")
            result = odomcal.reconstruct_and_calibrate(
                images, odometry_path, workspace, progress=lambda *step: steps.append(step),
                colmap_path="/nonexistent/colmap", mapper_attempts=2)
        self.assertEqual(result["status"], "unobservable", result["message"])
        self.assertIn("before COLMAP", result["message"])
        self.assertEqual(result["inputs"]["command"], "odomcal run")
        self.assertEqual(result["inputs"]["image_path"], images)
        self.assertIsNone(result["inputs"]["model_path"])
        self.assertEqual(result["options"]["run"]["mapper_attempts"], 2)
        self.assertEqual(result["options"]["run"]["colmap_path"], "/nonexistent/colmap")
        self.assertTrue(steps)
        stage, num_stages, fraction, message = steps[0]
        self.assertEqual(stage, 1)
        self.assertGreater(num_stages, 1)
        self.assertTrue(0.0 <= fraction <= 1.0)
        self.assertIsInstance(message, str)

    def test_colmap_failing_raises_runtime_error(self):
        camera, odometry = simulated_drive(duration_s=20)
        with tempfile.TemporaryDirectory() as folder:
            images = self.image_folder(folder, camera)
            odometry_path = os.path.join(folder, "odometry.csv")
            np.savetxt(odometry_path, odometry, fmt="%.17g", delimiter=",")
            with self.assertRaises(RuntimeError) as raised:
                odomcal.reconstruct_and_calibrate(
                    images, odometry_path, os.path.join(folder, "work"),
                    colmap_path="/nonexistent/colmap")
            self.assertIn("/nonexistent/colmap", str(raised.exception))
            with self.assertRaises(TypeError) as raised:
                odomcal.reconstruct_and_calibrate(images, odometry_path,
                                                  os.path.join(folder, "work"), progress=3)
            self.assertEqual(str(raised.exception),
                             "progress: expected a callable or None, got int")


if __name__ == "__main__":
    unittest.main()
