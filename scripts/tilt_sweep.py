#!/usr/bin/env python3
"""odomcal demo --simulated over seeds and ground tilts: error, stated 3 sigma, warnings (pure Python).

Usage: tilt_sweep.py <odomcal> <scratch folder> <seeds> <tilts,deg> [demo flags...]
A run that exits non-zero or writes no estimate (status other than success, no covariance)
is counted as refused, by its status, and left out of the error columns."""
import json, math, os, subprocess, sys, statistics

def mat(q):
    w, x, y, z = q
    return [[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)],
            [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)],
            [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]]

def mul_t(A, B):  # A B^T
    return [[sum(A[i][k] * B[j][k] for k in range(3)) for j in range(3)] for i in range(3)]

def log(R):
    angle = math.acos(max(-1, min(1, (R[0][0] + R[1][1] + R[2][2] - 1) / 2)))
    v = [(R[2][1] - R[1][2]) / 2, (R[0][2] - R[2][0]) / 2, (R[1][0] - R[0][1]) / 2]
    return v if angle < 1e-12 else [c * angle / math.sin(angle) for c in v]

def solve(C, e):
    n = len(e); M = [row[:] + [e[i]] for i, row in enumerate(C)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(M[r][i])); M[i], M[p] = M[p], M[i]
        for r in range(i + 1, n):
            f = M[r][i] / M[i][i]
            for c in range(i, n + 1): M[r][c] -= f * M[i][c]
    x = [0.0] * n
    for i in reversed(range(n)):
        x[i] = (M[i][n] - sum(M[i][c] * x[c] for c in range(i + 1, n))) / M[i][i]
    return x

odomcal, out, nseeds, tilts = sys.argv[1], sys.argv[2], int(sys.argv[3]), [float(t) for t in sys.argv[4].split(',')]
extra = sys.argv[5:]
def calibrated_row(ws, g):
    """The run's numbers, or None when it was refused: no calibration.json, or one without an
    estimate or covariance (status other than success, or keys missing/null)."""
    try:
        with open(f'{ws}/calibration.json') as f:
            r = json.load(f)
        q = r['odom_from_cam']['quaternion_wxyz']; t = r['odom_from_cam']['translation_m']
        C = r['covariance']['matrix']; scales = r['metric_scales']
        sd3 = 3 * (r['stddev']['roll_deg'] + r['stddev']['pitch_deg']) / 2
    except (OSError, ValueError, KeyError, TypeError, IndexError):
        return None
    phi = log(mul_t(mat(q), mat(g['odom_from_cam']['quaternion_wxyz'])))
    t_err = [t[k] - g['odom_from_cam']['translation_m'][k] for k in range(2)]
    e = phi + t_err + [scales[0] - g['metric_scale']]
    sd = [math.sqrt(C[k][k]) for k in range(6)]
    within = [abs(e[k]) <= 3 * sd[k] for k in range(6)]
    p = r['diagnostics'].get('planarity') or {}
    return dict(status=r['status'], warned=any('not planar' in w for w in r['warnings']),
                rot=math.degrees(math.sqrt(sum(c * c for c in phi))), rot_in=all(within[:3]),
                xy_in=all(within[3:5]), all_in=all(within), rp3=sd3,
                tilt=p.get('tilt_rms_deg', float('nan')),
                infl=math.sqrt(p.get('covariance_inflation', 1.0)))

print('| ground tilt (deg) | runs | refused | named (warning) | status | rotation error median / max (deg) | stated 3 sigma roll, pitch median (deg) | rotation within 3 sigma | x, y within 3 sigma | all 6 within 3 sigma | planarity tilt RMS median (deg) | inflation of sigma median |')
print('| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |')
for tilt in tilts:
    rows = []
    refused = {}  # status (or exit code) -> runs without an estimate to compare
    for seed in range(1, nseeds + 1):
        ws = f'{out}/t{tilt}_s{seed}'
        if os.path.exists(f'{ws}/calibration.json'):
            os.remove(f'{ws}/calibration.json')  # never read an earlier run's
        run = subprocess.run([odomcal, 'demo', '--simulated', '--seed', str(seed), '--ground_tilt_deg', str(tilt),
                              '--workspace_path', ws] + extra, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        row = None
        if run.returncode == 0:
            with open(f'{ws}/ground_truth.json') as f:
                row = calibrated_row(ws, json.load(f))
        if row is None:
            try:
                with open(f'{ws}/calibration.json') as f:
                    why = json.load(f).get('status', f'exit {run.returncode}')
            except (OSError, ValueError):
                why = f'exit={run.returncode}'
            refused[why] = refused.get(why, 0) + 1
            continue
        rows.append(row)
    why = ', '.join(f'{k} {v}' for k, v in refused.items()) or '0'
    if not rows:
        print(f"| {tilt:g} | {nseeds} | {why} | | | | | | | | | |", flush=True)
        continue
    c = lambda k: sum(1 for x in rows if x[k])
    st = {}
    for x in rows: st[x['status']] = st.get(x['status'], 0) + 1
    med = lambda k: statistics.median(x[k] for x in rows)
    print(f"| {tilt:g} | {nseeds} | {why} | {c('warned')} | {', '.join(f'{k} {v}' for k, v in st.items())} | "
          f"{med('rot'):.3f} / {max(x['rot'] for x in rows):.3f} | {med('rp3'):.3f} | {c('rot_in')} | {c('xy_in')} | "
          f"{c('all_in')} | {med('tilt'):.3f} | {med('infl'):.2f} |", flush=True)
