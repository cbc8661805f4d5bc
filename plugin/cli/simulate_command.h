// `odomcal simulate`: the Monte Carlo evaluation of Guo, Mirzaei &
// Roumeliotis (ICRA 2012), Section V (Fig. 2 and Table I), on the sweeps of
// datasets/paper/paper_sweeps.h with the methods of
// datasets/paper/paper_evaluation.h.
//
//   odomcal simulate --output_path DIR [--trials 1000] [--seed S]
//       [--sweep rotation_noise|translation_noise|pixel_noise|num_motions|all]
//       [--threads 2] [--camera_noise landmarks|parametric]
//       [--cm_iterations 200] [--overwrite]
//
// Writes, per sweep, DIR/<sweep>.csv (one row per sweep point and method:
// value, method, rmse_rotation_deg, rmse_translation_m, rmse_scale_rel,
// divergence_rate, failures, trials; an empty field where a value does not
// exist) and DIR/<sweep>.svg (panels: rotation, x/y translation and scale
// RMSE, divergence rate); and DIR/divergence.csv, Table I: divergences of the
// B methods pooled over every point run. Prints a table per sweep on stdout
// and, on a terminal, progress on stderr. Exit codes as for every command:
// 0 success, 2 bad arguments or outputs (existing files without
// --overwrite), 1 internal error.
#pragma once

namespace odomcal {

int RunSimulate(int argc, char** argv);

}  // namespace odomcal
