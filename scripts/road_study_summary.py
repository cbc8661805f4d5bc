#!/usr/bin/python3
"""The tables of scripts/road_study.sh from its results: per drive and
odometry (planar: `odomcal run`; SE(3): `odomcal colmap` on the same model;
planar, joint on: the same with `--joint_adjustment on`)
the status, the error of roll/pitch/yaw (about the odometry's axes) and
x/y/z against the truth and over the stated sigma; then per preset and
odometry how many drives gave an answer and, per parameter, how many lie
within 3 sigma and the RMS of error/sigma (1 when the sigma is honest);
and for drives run twice (ROAD_STUDY_REPEAT=1) the largest difference
between the two results.

    scripts/road_study_summary.py [ROOT (default /tmp/odomcal_road_study)] [PRESETS (default "road road_sloped")]
"""
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from calibration_errors import errors_and_sigmas  # noqa: E402

root = sys.argv[1] if len(sys.argv) > 1 else "/tmp/odomcal_road_study"
presets = (sys.argv[2] if len(sys.argv) > 2 else "road road_sloped").split()
params = ["roll", "pitch", "yaw", "x", "y", "z"]


def load(path):
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return None


def seconds(path):
    try:
        return float(open(path).read())
    except (OSError, ValueError):
        return None


print("| drive | odometry | wall | result | roll / pitch / yaw error (deg) | "
      "x / y / z error (mm) | error / sigma |")
print("| --- | --- | --- | --- | --- | --- | --- |")
totals = {}
repeats = []
for preset in presets:
    seeds = sorted(int(m.group(1)) for name in os.listdir(root)
                   if (m := re.fullmatch(re.escape(preset) + r"(\d+)", name))
                   and os.path.exists(os.path.join(root, name, "ground_truth.json")))
    for seed in seeds:
        name = f"{preset}{seed}"
        base = os.path.join(root, name)
        truth = json.load(open(os.path.join(base, "ground_truth.json")))["odom_from_cam"]
        for odometry, folder, timing in (("planar", "_ws", ".run.seconds"),
                                         ("SE(3)", "_se3", ".se3.seconds"),
                                         ("planar, joint on", "_on", ".on.seconds")):
            result = load(base + folder + "/calibration.json")
            if result is None:
                continue
            total = totals.setdefault((preset, odometry), {
                "drives": 0, "answers": 0, "adopted": 0, "ratios": {p: [] for p in params}})
            total["drives"] += 1
            wall = seconds(base + timing)
            wall_cell = f"{wall / 60:.1f} min" if wall is not None else ""
            measured = errors_and_sigmas(result, truth)
            if measured is None:
                print(f"| {name} | {odometry} | {wall_cell} | {result['status']} | | | |")
                continue
            total["answers"] += 1
            adopted = (result.get("joint_adjustment") or {}).get("adopted")
            total["adopted"] += 1 if adopted else 0
            errors, sigmas = measured
            ratio_cells = []
            for p, e, s in zip(params, errors, sigmas):
                if s is None:
                    ratio_cells.append("held")
                    continue
                total["ratios"][p].append(e / s)
                ratio_cells.append(f"{e / s:+.1f}")
            status = result["status"] + (", joint adjustment adopted" if adopted else "")
            print(f"| {name} | {odometry} | {wall_cell} | {status} | "
                  + " / ".join(f"{e:+.3f}" for e in errors[:3]) + " | "
                  + " / ".join(f"{1000 * e:+.1f}" if s is not None else "held"
                               for e, s in zip(errors[3:], sigmas[3:])) + " | "
                  + " / ".join(ratio_cells) + " |")
        repeat = load(base + "_repeat/calibration.json")
        first = load(base + "_ws/calibration.json")
        if repeat is not None and first is not None:
            a, b = first.get("odom_from_cam"), repeat.get("odom_from_cam")
            if a and b:
                difference = max(abs(u - v) for u, v in zip(
                    a["quaternion_wxyz"] + a["translation_m"],
                    b["quaternion_wxyz"] + b["translation_m"]))
                repeats.append(f"{name}: {first['status']} / {repeat['status']}, "
                               f"largest difference {difference:.3g}")
            else:
                repeats.append(f"{name}: {first['status']} / {repeat['status']}")
print()
for (preset, odometry), total in totals.items():
    parts = []
    for p in params:
        values = total["ratios"][p]
        if values:
            within = sum(1 for v in values if abs(v) <= 3)
            rms = math.sqrt(sum(v * v for v in values) / len(values))
            parts.append(f"{p} {within}/{len(values)} (RMS {rms:.2f})")
    print(f"- {preset}, {odometry} odometry: {total['answers']} answers of "
          f"{total['drives']} drives ({total['adopted']} from the joint adjustment); "
          "within 3 sigma: " + ", ".join(parts))
for line in repeats:
    print(f"- run twice, {line}")
