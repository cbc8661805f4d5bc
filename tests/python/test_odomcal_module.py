"""Unit tests of the Python module odomcal (python/odomcal_module.cc).

A noise-free planar drive made here with numpy, with a known odom_from_cam
and metric scale: the module must recover them from arrays and from files,
and reject bad keywords and arrays with the CLI's one-line messages.
Run by ctest with Debian's /usr/bin/python3 and PYTHONPATH=<build>/python.
"""
import math
import os
import tempfile
import unittest

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
             "odometry row 7: yaw jumps from %.6g to 45 rad, more than pi and not a 2 pi "
             "wrap (yaw must be in radians)" % odometry[6, 3]),
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

    def test_version(self):
        self.assertRegex(odomcal.__version__, r"^\d+\.\d+\.\d+$")


if __name__ == "__main__":
    unittest.main()
