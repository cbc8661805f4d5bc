#!/usr/bin/python3
"""The table of scripts/scene_sweep.sh from its results: per scene and method
(`odomcal colmap` on the model of `odomcal run` with `--joint_adjustment`
off: the two-step; check, the default; on: the joint adjustment) the error over the stated sigma of roll/pitch/yaw (about the
odometry's axes) and x, y, z, then per parameter how many lie within 3 sigma
and the RMS of error/sigma (1 when the sigma is honest).

    scripts/scene_sweep_summary.py [/tmp/odomcal_scene_sweep]
"""
import json
import math
import os
import sys

root = sys.argv[1] if len(sys.argv) > 1 else "/tmp/odomcal_scene_sweep"


adopted = []
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from calibration_errors import errors_and_sigmas  # noqa: E402
from colmap_images import camera_centres  # noqa: E402


def scale_error(result, folder, truth_images):
    """The metric model with most images: its camera path against the true
    one (sum of consecutive centre distances, images in name order), as
    (relative error, its stated relative sigma or None for the adjusted
    model, whose scale was adjusted along the drive)."""
    best = None
    for model in (result.get("colmap") or {}).get("metric_models") or []:
        images = os.path.join(folder, model["path"], "images.bin")
        if not os.path.exists(images):
            continue
        centres = camera_centres(images)
        if best is None or len(centres) > len(best[1]):
            best = (model, centres)
    if best is None or len(best[1]) < 2:
        return None
    model, centres = best
    names = sorted(n for n in centres if n in truth_images)
    true_length = sum(math.dist(truth_images[a], truth_images[b]) for a, b in zip(names, names[1:]))
    length = sum(math.dist(centres[a], centres[b]) for a, b in zip(names, names[1:]))
    if not length > 0:
        return None
    sigma = None
    if model.get("origin_from_sfm") is not None:
        rel = (result.get("stddev") or {}).get("metric_scales_rel") or []
        if model["segment"] < len(rel) and rel[model["segment"]]:
            sigma = rel[model["segment"]]
    return length / true_length - 1.0, sigma


params = ["roll", "pitch", "yaw", "x", "y", "z", "scale"]
methods = (("two_step", "off"), ("check", "check"), ("joint", "on"))
ratios = {method: {p: [] for p in params} for method, _ in methods}
print("| scene | method | roll / pitch / yaw error over sigma | x / y / z error over sigma | "
      "x / y / z error (mm) | scale error (over sigma) | z from |")
print("| --- | --- | --- | --- | --- | --- | --- |")
for name in sorted(os.listdir(root)):
    truth_path = os.path.join(root, name, "data", "ground_truth.json")
    if not os.path.exists(truth_path):
        continue
    truth_json = json.load(open(truth_path))
    truth = truth_json["odom_from_cam"]
    truth_images = {i["name"]: i["world_from_cam"]["translation_m"] for i in truth_json["images"]}
    for method, folder in methods:
        path = os.path.join(root, name, folder, "calibration.json")
        if not os.path.exists(path):
            continue
        r = json.load(open(path))
        measured = errors_and_sigmas(r, truth)
        if measured is None:
            print(f"| {name} | {method.replace('_', '-')} | {r['status']} | | | | |")
            continue
        if method == "check" and (r.get("joint_adjustment") or {}).get("adopted"):
            adopted.append(name)
        errors, sigmas = measured
        cells = []
        for p, err, sig in zip(params, errors, sigmas):
            if sig is None:
                cells.append("held")
                continue
            ratios[method][p].append(err / sig)
            cells.append(f"{err / sig:+.1f}")
        mm = " / ".join(f"{1000 * v:+.1f}" for v in errors[3:])
        scale = scale_error(r, os.path.join(root, name, folder), truth_images)
        scale_cell = ""
        if scale is not None:
            scale_cell = f"{100 * scale[0]:+.2f} %"
            if scale[1]:
                ratios[method]["scale"].append(scale[0] / scale[1])
                scale_cell += f" ({scale[0] / scale[1]:+.1f})"
        print(f"| {name} | {method.replace('_', '-')} | {' / '.join(cells[:3])} | "
              f"{' / '.join(cells[3:])} | {mm} | {scale_cell} | {r.get('translation_z_source')} |")
print()
for method, _ in methods:
    parts = []
    for p in params:
        v = ratios[method][p]
        if v:
            within = sum(1 for x in v if abs(x) <= 3)
            rms = math.sqrt(sum(x * x for x in v) / len(v))
            parts.append(f"{p} {within}/{len(v)} within 3 sigma, RMS {rms:.2f}")
    print(f"- {method.replace('_', '-')}: " + "; ".join(parts))
print("- check: the joint adjustment's estimate reported (a contradicted two-step) on "
      + (", ".join(adopted) if adopted else "no scene"))
