#!/usr/bin/env python3
"""A rig calibration against its rendered truth: per camera its rotation and
translation error with the stated 3 sigma, per camera-to-camera transform its
errors and the largest error over sigma.

    scripts/rig_errors.py DATA WORKSPACE SECONDS LABEL

DATA: a folder written by `odomcal render --rig` (ground_truth.json);
WORKSPACE: where calibration.json was written; SECONDS and LABEL head the
printout. Used by scripts/rig_study.sh and scripts/rig_project_study.sh.
"""
import json, sys
import numpy as np
data, ws, seconds, label = sys.argv[1:5]
truth = json.load(open(f"{data}/ground_truth.json"))
result = json.load(open(f"{ws}/calibration.json"))
def transform(t):
    w, x, y, z = t["quaternion_wxyz"]
    q = np.array([w, x, y, z])
    R = np.array([[1-2*(y*y+z*z), 2*(x*y-z*w), 2*(x*z+y*w)],
                  [2*(x*y+z*w), 1-2*(x*x+z*z), 2*(y*z-x*w)],
                  [2*(x*z-y*w), 2*(y*z+x*w), 1-2*(x*x+y*y)]])
    return R, np.array(t["translation_m"])
def angle(R):
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1)))
def left_perturbation(E):
    # The rotation vector phi of E = Exp(phi), radians.
    psi = np.array([E[2, 1] - E[1, 2], E[0, 2] - E[2, 0], E[1, 0] - E[0, 1]])
    return psi * np.arccos(np.clip((np.trace(E) - 1) / 2, -1, 1)) / max(
        np.linalg.norm(psi), 1e-300)
truths = {c["name"]: transform(c["odom_from_cam"]) for c in truth["cameras"]}
print(f"{label}: {float(seconds):.0f} s")
for camera in result["cameras"]:
    name = camera["name"]
    if camera["status"] != "success":
        print(f"  {name:11s} {camera['status']}: {camera['reason'][:110]}")
        continue
    R, t = transform(camera["odom_from_cam"])
    Rt, tt = truths[name]
    e = 1000 * (t - tt)
    sd = camera["stddev"]
    # Left perturbation about the odometry's axes, as the covariance's.
    sigmas = np.concatenate([
        np.abs(left_perturbation(R @ Rt.T)) / np.radians(sd["rotation_axes_deg"]),
        np.abs(e[:2]) / (1000 * np.array([sd["translation_x_m"], sd["translation_y_m"]]))])
    print(f"  {name:11s} rotation {angle(Rt.T @ R):.3f} deg, x {e[0]:+.1f} y {e[1]:+.1f} "
          f"z {e[2]:+.1f} mm (z {camera['translation_z_source']}), "
          f"3 sigma x {3000*sd['translation_x_m']:.1f} y {3000*sd['translation_y_m']:.1f} mm; "
          f"largest error/sigma rotation {sigmas[:3].max():.1f}, x/y {sigmas[3:].max():.1f}")
for pair in result["camera_pairs"]:
    a, b = pair["camera_a"], pair["camera_b"]
    Ra, ta = truths[a]; Rb, tb = truths[b]
    R_true = Rb.T @ Ra; t_true = Rb.T @ (ta - tb)
    R, t = transform(pair["camb_from_cama"])
    # Left perturbation about camB's axes, and the translation in camB.
    psi = left_perturbation(R @ R_true.T)
    sd = pair["stddev"]
    r_sigmas = np.abs(psi) / np.radians(sd["rotation_axes_deg"])
    t_sigmas = np.abs(t - t_true) / np.array(sd["translation_m"])
    if pair["odom_offset_z_held"]:
        t_sigmas = t_sigmas[:0]  # the held heights' difference: not measured
    print(f"  {b}_from_{a}: rotation {angle(R_true.T @ R):.3f} deg, "
          f"translation {1000*np.linalg.norm(t - t_true):.1f} mm; "
          f"3 sigma rotation {3*max(sd['rotation_axes_deg']):.3f} deg; "
          f"largest error/sigma rotation {r_sigmas.max():.1f}"
          + (f", translation {t_sigmas.max():.1f}" if len(t_sigmas) else "")
          + (" (adjusted together)" if pair.get("adjusted_together") else ""))
for shared in result.get("shared_scales", []):
    sigmas = shared["difference_sigmas"]
    print(f"  sub-model {shared['sub_model'] or '0'}: scales of {shared['camera_a']} and "
          f"{shared['camera_b']} differ by "
          f"{100 * (shared['metric_scale_b'] / shared['metric_scale_a'] - 1):+.2f} %"
          + (f" ({sigmas:+.1f} sigma)" if sigmas is not None else ""))
joint = result.get("rig_joint_adjustment")
if joint and joint.get("status") == "success":
    print(f"  adjusted together: {joint['num_images']} images, {joint['num_points']} points "
          f"({joint['num_points_across_cameras']} seen by several cameras), "
          f"{joint['num_links']} odometry links")
