#!/usr/bin/env python3
"""Markdown tables of an `odomcal simulate` output folder, as in
docs/paper_reproduction.md ("Measured tables").

  scripts/paper_tables.py FOLDER

Each cell: rotation RMSE [deg] / x-y RMSE [mm] / scale RMSE [%]; for the B
methods, in bold, the divergence rate [%] and, where the CSV has the column,
the mean fraction of motions in the final refinement [%]. Then Table I from
divergence.csv. Reads only the CSVs the folder holds.
"""
import csv
import os
import sys

SWEEPS = [
    ("rotation_noise", "odometry yaw SD [rad]"),
    ("translation_noise", "odometry translation SD [fraction of length]"),
    ("pixel_noise", "image noise SD [px]"),
    ("num_motions", "motions"),
]
METHODS = ["ALS", "ALSP-L", "ALSP-orth", "CM", "ALS-B", "ALSP-L-B", "CM-B", "GT-B"]


def cell(row):
    text = "%.3f / %.2f / %.2f" % (
        float(row["rmse_rotation_deg"]),
        1000.0 * float(row["rmse_translation_m"]),
        100.0 * float(row["rmse_scale_rel"]),
    )
    if row["divergence_rate"]:
        text += "; **%.1f**" % (100.0 * float(row["divergence_rate"]))
        if row.get("motions_used"):
            text += " (%.1f)" % (100.0 * float(row["motions_used"]))
    return text


def main(folder):
    for sweep, label in SWEEPS:
        path = os.path.join(folder, sweep + ".csv")
        if not os.path.exists(path):
            continue
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        trials = rows[0]["trials"]
        used = "; (motions used [%])" if rows[0].get("motions_used") is not None else ""
        print("**%s** (%s; %s trials per point) — rotation RMSE [deg] / x-y RMSE [mm] / "
              "scale RMSE [%%]; divergence [%%] for the B methods%s\n" % (sweep, label, trials, used))
        print("| value | " + " | ".join(METHODS) + " |")
        print("|---" * (len(METHODS) + 1) + "|")
        values = []
        for row in rows:
            if row["value"] not in values:
                values.append(row["value"])
        for value in values:
            by_method = {r["method"]: r for r in rows if r["value"] == value}
            print("| %s | " % value + " | ".join(cell(by_method[m]) for m in METHODS) + " |")
        print()
    path = os.path.join(folder, "divergence.csv")
    if os.path.exists(path):
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
        print("**Table I** (pooled over all sweep points)\n")
        print("| | " + " | ".join(r["method"] for r in rows) + " |")
        print("|---" * (len(rows) + 1) + "|")
        print("| divergence | " + " | ".join(
            "%.2f %% (%s/%s)" % (100.0 * float(r["divergence_rate"]), r["divergences"],
                                 r["trials_with_covariance"]) for r in rows) + " |")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: paper_tables.py FOLDER")
    main(sys.argv[1])
