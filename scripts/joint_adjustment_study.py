#!/usr/bin/env python3
"""The joint adjustment against the truth on rendered scenes.

For each seed: `odomcal render --preset PRESET`, then `odomcal run` with the
true intrinsics and wheel track and --joint_adjustment on, and compares with the scene's
ground_truth.json:
  - the extrinsic's rotation error per odometry axis (deg) and x/y error (mm),
    for the joint estimate and the two-step one (diagnostics.two_step), and
    the joint errors over their stated standard deviations (z-scores);
  - the metric model's camera centres against the true ones, nothing but the
    calibration applied (RMS and worst, mm, and the worst over the path).
Prints one line per seed and a summary (RMS of the errors and z-scores,
the share of components within 3 sigma).

  scripts/joint_adjustment_study.py [--preset small] [--seeds 1-6]
      [--odomcal build/plugin/odomcal] [--work /tmp/joint_study]
      [--repeat N] [--reuse OUTPUT] [-- FLAGS]
"""
import argparse
import json
import math
import os
import shutil
import subprocess
import sys

import numpy as np

from colmap_images import camera_centres


def rotation(q_wxyz):
    w, x, y, z = q_wxyz
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def log_rotation(r):
    angle = math.acos(max(-1.0, min(1.0, (np.trace(r) - 1.0) / 2.0)))
    if angle < 1e-12:
        return np.zeros(3)
    return angle / (2.0 * math.sin(angle)) * np.array(
        [r[2, 1] - r[1, 2], r[0, 2] - r[2, 0], r[1, 0] - r[0, 1]])


def errors(result_transform, truth):
    r_true = rotation(truth["odom_from_cam"]["quaternion_wxyz"])
    rot = log_rotation(rotation(result_transform["quaternion_wxyz"]) @ r_true.T)
    t = np.array(result_transform["translation_m"][:2]) - np.array(
        truth["odom_from_cam"]["translation_m"][:2])
    return np.degrees(rot), 1e3 * t


def run_seed(args, seed, extra, repetition=0):
    data = os.path.join(args.work, "%s_%d" % (args.preset, seed))
    workspace = data + ("_ws" if not repetition else "_ws_run%d" % repetition)
    if not os.path.isdir(data):
        subprocess.run([args.odomcal, "render", "--preset", args.preset, "--seed", str(seed),
                        "--output_path", data], check=True, stdout=subprocess.DEVNULL)
    truth = json.load(open(os.path.join(data, "ground_truth.json")))
    # The robot's wheel track, as its owner knows it: with unequal wheels
    # it determines the lever arm's y (docs/systematics.md).
    timing = ["--odometry", os.path.join(data, "odometry.csv"),
              "--image_timestamps", os.path.join(data, "image_timestamps.csv"),
              "--wheel_track_m", repr(truth["odometry_noise"]["wheel_base_m"])]
    if args.reuse:
        # The COLMAP model of an earlier run of this seed, calibrated again.
        model = os.path.join(workspace, "sparse")
        output = os.path.join(args.reuse, "%s_%d" % (args.preset, seed))
        shutil.rmtree(output, ignore_errors=True)
        subprocess.run([args.odomcal, "colmap", "--model_path", model, "--output_path", output,
                        "--joint_adjustment", "on"] + timing + extra,
                       check=True, stdout=subprocess.DEVNULL)
        workspace = output
    else:
        shutil.rmtree(workspace, ignore_errors=True)
        params = ",".join(repr(v) for v in truth["camera"]["params"])
        subprocess.run([args.odomcal, "run", "--image_path", os.path.join(data, "images"),
                        "--camera_model", truth["camera"]["model"], "--camera_params", params,
                        "--workspace_path", workspace, "--joint_adjustment", "on"] + timing
                       + extra, check=True, stdout=subprocess.DEVNULL)
    result = json.load(open(os.path.join(workspace, "calibration.json")))
    joint_rot, joint_xy = errors(result["odom_from_cam"], truth)
    sd = result["stddev"]
    stated = np.array(sd["rotation_axes_deg"] + [1e3 * sd["translation_x_m"],
                                                  1e3 * sd["translation_y_m"]])
    z = np.concatenate([joint_rot, joint_xy]) / stated
    two_step = result["diagnostics"].get("two_step")
    two_rot, two_xy = errors(two_step["odom_from_cam"], truth) if two_step else (None, None)
    truth_centres = {image["name"]: np.array(image["world_from_cam"]["translation_m"])
                     for image in truth["images"]}
    distances = []
    metric = os.path.join(workspace, "sparse_metric")
    for model in sorted(os.listdir(metric)):
        for name, centre in camera_centres(os.path.join(metric, model, "images.bin")).items():
            distances.append(np.linalg.norm(np.array(centre) - truth_centres[name]))
    names = sorted(truth_centres)
    path = sum(np.linalg.norm(truth_centres[b] - truth_centres[a]) for a, b in zip(names, names[1:]))
    joint = result["joint_adjustment"]
    print("seed %d%s: %s; joint rot [%s] deg x/y [%s] mm, z [%s]; two-step rot [%s] deg x/y [%s] mm; "
          "centres rms %.2f mm, worst %.2f mm (%.3f %% of %.1f m); %.1f s; %d warnings"
          % (seed, " run %d" % repetition if repetition else "", joint["status"], " ".join("%+.4f" % v for v in joint_rot),
             " ".join("%+.2f" % v for v in joint_xy), " ".join("%+.2f" % v for v in z),
             " ".join("%+.4f" % v for v in two_rot) if two_step else "-",
             " ".join("%+.2f" % v for v in two_xy) if two_step else "-",
             1e3 * math.sqrt(np.mean(np.square(distances))), 1e3 * max(distances),
             100 * max(distances) / path, path, joint.get("time_s", 0.0),
             len(result["warnings"])), flush=True)
    for warning in result["warnings"]:
        print("  warning: " + warning, flush=True)
    return joint_rot, joint_xy, z, two_rot, two_xy


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="small")
    parser.add_argument("--seeds", default="1-6")
    parser.add_argument("--odomcal", default="build/plugin/odomcal")
    parser.add_argument("--work", default="/tmp/joint_study")
    parser.add_argument("--repeat", type=int, default=1,
                        help="map and calibrate each seed this many times (COLMAP's run-to-run "
                             "spread), each in its own workspace")
    parser.add_argument("--reuse", metavar="OUTPUT",
                        help="calibrate the COLMAP models of an earlier run in --work again "
                             "(odomcal colmap, results in OUTPUT) instead of mapping anew")
    args, extra = parser.parse_known_args()
    extra = [e for e in extra if e != "--"]
    first, _, last = args.seeds.partition("-")
    os.makedirs(args.work, exist_ok=True)
    seeds = range(int(first), int(last or first) + 1)
    rows = [run_seed(args, seed, extra, repetition) for seed in seeds
            for repetition in (range(1, args.repeat + 1) if args.repeat > 1 else [0])]
    z = np.array([row[2] for row in rows])
    joint = np.array([np.concatenate([row[0], row[1]]) for row in rows])
    two = np.array([np.concatenate([row[3], row[4]]) for row in rows if row[3] is not None])
    rms = lambda a: np.sqrt(np.mean(np.square(a), axis=0))
    print("RMS error joint    rx ry rz [deg] x y [mm]: " + " ".join("%.4f" % v for v in rms(joint)))
    if len(two):
        print("RMS error two-step rx ry rz [deg] x y [mm]: " + " ".join("%.4f" % v for v in rms(two)))
    print("RMS z-score (error / stated sigma): " + " ".join("%.2f" % v for v in rms(z)))
    print("within 3 sigma: %d of %d components" % (np.sum(np.abs(z) <= 3.0), z.size))


if __name__ == "__main__":
    sys.exit(main())
