"""Paired stats and hand-orientation residual for the arm_6-only compliance models.
Usage: python compliance_arm6.py"""
import numpy as np
from tiago_compliance import *

def orient_err(spec, x):
    pr = predict(spec, x, np.arange(N)); out = []
    for i in range(N):
        A = pr[i] - pr[i].mean(0); B = Y[i, :spec.npts] - Y[i, :spec.npts].mean(0)
        U, S, Vt = np.linalg.svd(A.T @ B)
        D = np.diag([1, 1, np.sign(np.linalg.det(Vt.T @ U.T))])
        out.append(np.degrees(np.linalg.norm(Rot.from_matrix(Vt.T @ D @ U.T).as_rotvec())))
    return np.array(out)
E = {}
for name, s in [('A1', MODELS['A1']), ('A4', MODELS['A4']), ('B1_6', Spec(1, BIAS, [6], False)), ('B4_6', Spec(4, BIAS, [6], False)),
                ('B1_67', Spec(1, BIAS, [6, 7], False)), ('B4_67', Spec(4, BIAS, [6, 7], False))]:
    errs, P, rf, trn = cv(s); E[name] = errs
    o = 6 + 3 * s.npts + len(s.bias_j)
    print(f'{name:6s} mean {errs.mean():.3f} rms {np.sqrt((errs**2).mean()):.3f} worst {errs.max():.2f} (row {errs.argmax()}) '
          f'median {np.median(errs):.3f}; c folds {P[:, o:].mean(0)} +- {P[:, o:].std(0)}; biases full {s.unpack(rf.x)[2].round(4)}')
    if s.npts == 4:
        oe = orient_err(s, rf.x); print(f'       full-fit hand orientation error mean {oe.mean():.3f} max {oe.max():.3f} deg')
for a, b in [('B1_6', 'A1'), ('B4_6', 'A1'), ('B4_6', 'B1_6'), ('A4', 'A1'), ('B4_67', 'B1_67'), ('B4_67', 'A1')]:
    d = E[a] - E[b]; print(f'{a}-{b}: {d.mean():+.3f} +- {d.std(ddof=1)/np.sqrt(N):.3f} mm, better in {np.sum(d<0)}/37')
