"""A calibration.json against a rendered scene's ground_truth.json: the
rotation error about the odometry's axes and the translation error, with the
result's stated standard deviations. Quaternions are Hamilton, w x y z."""
import math


def matrix(q):
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def rotation_error_deg(estimate, truth):
    """e with truth = Exp(e) * estimate, about the odometry's axes."""
    Re, Rt = matrix(estimate), matrix(truth)
    D = [[sum(Rt[i][k] * Re[j][k] for k in range(3)) for j in range(3)] for i in range(3)]
    a = math.acos(max(-1.0, min(1.0, (D[0][0] + D[1][1] + D[2][2] - 1) / 2)))
    s = 0.5 if a < 1e-12 else a / (2 * math.sin(a))
    return [math.degrees(s * (D[2][1] - D[1][2])), math.degrees(s * (D[0][2] - D[2][0])),
            math.degrees(s * (D[1][0] - D[0][1]))]


def errors_and_sigmas(result, truth):
    """([roll, pitch, yaw] error in deg + [x, y, z] error in m, the six
    stated sigmas, None where held), or None without an estimate."""
    q = (result.get("odom_from_cam") or {}).get("quaternion_wxyz")
    if result.get("status") != "success" or q is None:
        return None
    sd = result["stddev"]
    sigmas = list(sd["rotation_axes_deg"]) + [
        sd["translation_x_m"], sd["translation_y_m"], sd["translation_z_m"]]
    # z held under its prior and moved by the data (SE(3) odometry's tilts):
    # its uncertainty is the prior's posterior.
    prior = result.get("translation_z_prior") or {}
    if sigmas[5] is None and prior.get("moved_by_data"):
        sigmas[5] = prior.get("stddev_m")
    sigmas = [s if s is not None and s > 0 else None for s in sigmas]
    t = result["odom_from_cam"]["translation_m"]
    errors = rotation_error_deg(q, truth["quaternion_wxyz"]) + [
        t[k] - truth["translation_m"][k] for k in range(3)]
    return errors, sigmas
