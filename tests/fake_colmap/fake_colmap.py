#!/usr/bin/env python3
"""A stand-in for another COLMAP (or GLOMAP) version, for odomcal's tests.

    fake_colmap.py --emulate VERSION --real COLMAP_3_8 [COLMAP ARGUMENTS...]

VERSION is a COLMAP release (3.8, 3.9.1, 3.10, 3.11.1, 3.12.6, 3.13.0,
4.0.4, 4.1.1) or "glomap" (GLOMAP 1.x). `help` prints that release's banner;
a command accepts exactly the option names that release registers for it
(of the options odomcal uses: the tables below, read from COLMAP's
option_manager.cc and exe/*.cc at each release tag, and from GLOMAP's
exe/global_mapper.cc and controllers/option_manager.cc), refusing any other
as COLMAP does (exit 1, "unrecognised option"); the accepted command is then
translated to COLMAP 3.8's names and run by the real COLMAP 3.8. So odomcal's
whole `run` pipeline works against each version's command line, and a name
that version does not know fails the stage as it would with that COLMAP.

Not emulated: the models a 3.12+ COLMAP writes carry rigs and frames (the
model readers are tested on those separately); databases stay 3.8's.
"""
import os
import sys


def parse_version(text):
    parts = [int(p) for p in text.replace("-dev", "").split(".")]
    while len(parts) < 3:
        parts.append(0)
    return tuple(parts[:3])


def banner(version_text, version):
    if version >= (4, 1, 0):
        return "COLMAP %s (Commit 1a2b3c4 on 2026-07-17 without CUDA)" % version_text
    if version >= (3, 9, 0):
        return ("COLMAP %s -- Structure-from-Motion and Multi-View Stereo\n"
                "(Commit 1a2b3c4 on 2025-11-07 without CUDA)" % version_text)
    return ("COLMAP %s -- Structure-from-Motion and Multi-View Stereo\n"
            "              (Commit Unknown on Unknown without CUDA)" % version_text)


def colmap_options(command, v):
    """{name in version v: name in COLMAP 3.8 (None: dropped)} for `command`."""
    common = {"log_to_stderr": "log_to_stderr", "log_level": "log_level",
              "project_path": "project_path"}
    if v >= (3, 13, 0):
        common["default_random_seed"] = "random_seed"
    else:
        common["random_seed"] = "random_seed"
    extraction = "FeatureExtraction" if v >= (3, 13, 0) else "SiftExtraction"
    matching = "FeatureMatching" if v >= (3, 13, 0) else "SiftMatching"
    tables = {
        "feature_extractor": {
            "database_path": "database_path", "image_path": "image_path",
            "image_list_path": "image_list_path",
            "ImageReader.single_camera": "ImageReader.single_camera",
            "ImageReader.camera_model": "ImageReader.camera_model",
            "ImageReader.camera_params": "ImageReader.camera_params",
            extraction + ".use_gpu": "SiftExtraction.use_gpu",
            extraction + ".num_threads": "SiftExtraction.num_threads",
            # Every release keeps the SIFT options under SiftExtraction.
            "SiftExtraction.max_num_features": "SiftExtraction.max_num_features",
        },
        "mapper": {
            "database_path": "database_path", "image_path": "image_path",
            "output_path": "output_path", "input_path": "input_path",
            "Mapper.num_threads": "Mapper.num_threads",
            "Mapper.ba_refine_focal_length": "Mapper.ba_refine_focal_length",
            "Mapper.ba_refine_principal_point": "Mapper.ba_refine_principal_point",
            "Mapper.ba_refine_extra_params": "Mapper.ba_refine_extra_params",
            "Mapper.init_min_tri_angle": "Mapper.init_min_tri_angle",
            "Mapper.init_max_forward_motion": "Mapper.init_max_forward_motion",
            "Mapper.init_image_id1": "Mapper.init_image_id1",
            "Mapper.init_image_id2": "Mapper.init_image_id2",
            "Mapper.init_min_num_inliers": "Mapper.init_min_num_inliers",
        },
        "point_triangulator": {
            "database_path": "database_path", "image_path": "image_path",
            "input_path": "input_path", "output_path": "output_path",
            "clear_points": "clear_points",
        },
        "bundle_adjuster": {
            "input_path": "input_path", "output_path": "output_path",
            "BundleAdjustment.refine_focal_length": "BundleAdjustment.refine_focal_length",
            "BundleAdjustment.refine_principal_point": "BundleAdjustment.refine_principal_point",
            "BundleAdjustment.refine_extra_params": "BundleAdjustment.refine_extra_params",
        },
        "database_cleaner": {"type": "type", "database_path": "database_path"},
    }
    if v >= (3, 13, 0):
        tables["mapper"]["Mapper.image_list_path"] = "image_list_path"
        tables["mapper"]["Mapper.random_seed"] = None
    else:
        tables["mapper"]["image_list_path"] = "image_list_path"
    for matcher in ("exhaustive_matcher", "sequential_matcher",
                    "spatial_matcher", "matches_importer"):
        table = {"database_path": "database_path",
                 matching + ".use_gpu": "SiftMatching.use_gpu",
                 matching + ".num_threads": "SiftMatching.num_threads"}
        if matcher == "sequential_matcher":
            table["SequentialMatching.overlap"] = "SequentialMatching.overlap"
        if matcher == "spatial_matcher":
            for name in ("ignore_z", "max_num_neighbors", "max_distance"):
                table["SpatialMatching." + name] = "SpatialMatching." + name
            if v < (3, 10, 0):
                table["SpatialMatching.is_gps"] = "SpatialMatching.is_gps"
        if matcher == "matches_importer":
            table["match_list_path"] = "match_list_path"
            table["match_type"] = "match_type"
        tables[matcher] = table
    if v >= (4, 0, 0):
        tables["global_mapper"] = {
            "database_path": "database_path", "image_path": "image_path",
            "output_path": "output_path",
            "GlobalMapper.image_list_path": "image_list_path",
            "GlobalMapper.num_threads": "Mapper.num_threads",
            "GlobalMapper.random_seed": "random_seed",
            "GlobalMapper.ba_refine_focal_length": "Mapper.ba_refine_focal_length",
            "GlobalMapper.ba_refine_principal_point": "Mapper.ba_refine_principal_point",
            "GlobalMapper.ba_refine_extra_params": "Mapper.ba_refine_extra_params",
        }
    if command not in tables:
        return None
    table = dict(common)
    table.update(tables[command])
    return table


def glomap_options(command):
    if command != "mapper":
        return None
    return {"database_path": "database_path", "image_path": "image_path",
            "output_path": "output_path", "constraint_type": None,
            "output_format": None,
            "BundleAdjustment.optimize_intrinsics": "Mapper.ba_refine_focal_length",
            "BundleAdjustment.optimize_principal_point": "Mapper.ba_refine_principal_point"}


def refuse(message):
    sys.stderr.write(message + "\n")
    sys.exit(1)


def main(argv):
    if len(argv) < 4 or argv[0] != "--emulate" or argv[2] != "--real":
        refuse("usage: fake_colmap.py --emulate VERSION --real COLMAP [ARGS...]")
    emulate, real, arguments = argv[1], argv[3], argv[4:]
    glomap = emulate == "glomap"
    version = None if glomap else parse_version(emulate)
    if not arguments or arguments[0] in ("help", "-h", "--help"):
        if glomap:
            print("GLOMAP -- Global Structure-from-Motion\n\n"
                  "Usage:\n  glomap mapper --database_path DATABASE "
                  "--output_path MODEL")
        else:
            print(banner(emulate, version) + "\n\nUsage:\n  colmap [command] [options]")
        return 0
    command, rest = arguments[0], arguments[1:]
    table = glomap_options(command) if glomap else colmap_options(command, version)
    if table is None:
        refuse("Command `%s` not recognized." % command)
    translated = []
    given = {}
    if len(rest) % 2 != 0:
        refuse("ERROR: Failed to parse options - odd number of arguments.")
    for k in range(0, len(rest), 2):
        flag, value = rest[k], rest[k + 1]
        if not flag.startswith("--") or flag[2:] not in table:
            refuse("ERROR: Failed to parse options - unrecognised option '%s'." % flag)
        given[flag[2:]] = value
        target = table[flag[2:]]
        if target is not None:
            translated += ["--" + target, value]
    real_command = command
    if command == "global_mapper" or glomap:
        real_command = "mapper"
        output = given.get("output_path", "")
        if not os.path.isdir(output):
            refuse("ERROR: `output_path` is not a directory: " + output)
        if glomap and "BundleAdjustment.optimize_intrinsics" in given:
            translated += ["--Mapper.ba_refine_extra_params",
                           given["BundleAdjustment.optimize_intrinsics"]]
    sys.stdout.flush()
    os.execvp(real, [real, real_command] + translated)
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
