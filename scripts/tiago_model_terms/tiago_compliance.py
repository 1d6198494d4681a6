"""Gravity-compliance experiment on the TIAGo Qualisys static postures.

Usage: python tiago_compliance.py [MODEL ...]   (see README.md here)

Models (q_j = reading_j - b_j, gains 1):
  A  : mocap frame (6) + marker point(s) in wrist_ft_tool_link (3/pt) + biases arm_2..arm_6 (5)
  B  : A + per-joint compliance c_j:  q_eff_j = q_j + c_j * tau_j(q_enc),
       tau = pinocchio computeGeneralizedGravity at encoder readings (g=9.81, -z base)
       (arm_1 axis is vertical -> tau_1 == 0 identically, so c_1 is not identifiable)
  C  : A + 3-param compliance of the F/T sensor: rotation of the hand (links after
       wrist_ft_link) about the wrist_ft_link origin, rotvec = diag(k) @ tau_hand,
       tau_hand = gravity moment of the hand about wrist_ft_link origin, in wrist_ft_link axes.
  suffix 1 = point 1 only ; 4 = all four points (12 residuals / posture)
Protocol: 5 interleaved folds (row i held out in fold i%5); held-out point-1 error.
"""
import sys, json, tempfile, time
import numpy as np
import pinocchio as pin
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation as Rot

import os
DATA = os.environ.get('TIAGO_DIR', os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..', '..', 'shared', 'realdata', 'tiago'))
URDF = os.path.join(DATA, 'tiago_48_schunk.urdf')
CSV = os.path.join(DATA, 'qualisys_2021-11-30_static_postures.csv')

model = pin.buildModelFromUrdf(URDF)
data = model.createData()
JN = ['torso_lift_joint'] + [f'arm_{k}_joint' for k in range(1, 8)]
JID = [model.getJointId(n) for n in JN]
QIDX = [model.idx_qs[j] for j in JID]
VIDX = [model.idx_vs[j] for j in JID]
FT_TOOL = model.getFrameId('wrist_ft_tool_link')
FT_LINK = model.getFrameId('wrist_ft_link')

raw = np.genfromtxt(CSV, delimiter=',', names=True)
N = len(raw)
Y = np.stack([np.stack([raw[f'{c}{k}'] for c in 'xyz'], 1) for k in range(1, 5)], 1)  # N x 4 x 3
QR = np.stack([raw[n] for n in JN], 1)  # N x 8 encoder readings

q0 = pin.neutral(model)


def full_q(qa):
    q = q0.copy()
    q[QIDX] = qa
    return q


# ---------- gravity torques at the encoder readings ----------
TAU = np.zeros((N, 8))
for i in range(N):
    g = pin.computeGeneralizedGravity(model, data, full_q(QR[i]))
    TAU[i] = g[VIDX]

# ---------- hand (downstream of wrist_ft_link) mass & COM in wrist_ft_link frame ----------
def hand_mass_com():
    # frames attached to joint arm_7 that are "after" wrist_ft_link in the chain, plus finger bodies
    import xml.etree.ElementTree as ET
    root = ET.parse(URDF).getroot()
    children = {}
    for j in root.findall('joint'):
        children.setdefault(j.find('parent').get('link'), []).append(j.find('child').get('link'))
    sub, stack = [], ['wrist_ft_link']
    while stack:
        l = stack.pop(); sub.append(l); stack += children.get(l, [])
    q = full_q(np.zeros(8))
    pin.forwardKinematics(model, data, q); pin.updateFramePlacements(model, data)
    Tw = data.oMf[FT_LINK]
    links = {l.get('name'): l for l in root.findall('link')}
    M, S = 0.0, np.zeros(3)
    for l in sub:
        inn = links[l].find('inertial')
        if inn is None:
            continue
        m = float(inn.find('mass').get('value'))
        org = inn.find('origin')
        xyz = np.array([float(v) for v in org.get('xyz').split()]) if org is not None else np.zeros(3)
        fid = model.getFrameId(l)
        Tl = Tw.inverse() * data.oMf[fid]
        S += m * (Tl.act(xyz)); M += m
    # the 'wrist_ft_link' inertial itself is on the sensor's fixed (arm) side? keep it included: it is
    # the sensor body; a variant without it is just a different scalar of k.
    return M, S / M, sub

HAND_M, HAND_C, HAND_LINKS = hand_mass_com()


def hand_torque(qa):
    pin.forwardKinematics(model, data, full_q(qa)); pin.updateFramePlacements(model, data)
    R = data.oMf[FT_LINK].rotation
    gl = R.T @ np.array([0, 0, -9.81]) * HAND_M  # gravity force in wrist_ft_link axes
    return np.cross(HAND_C, gl)

TAUH = np.array([hand_torque(QR[i]) for i in range(N)])
T_FT_TOOL = None
pin.forwardKinematics(model, data, full_q(np.zeros(8))); pin.updateFramePlacements(model, data)
T_FT_TOOL = data.oMf[FT_LINK].inverse() * data.oMf[FT_TOOL]


# ---------- model ----------
class Spec:
    def __init__(self, npts, bias_j, comp_j, ftcomp):
        self.npts, self.bias_j, self.comp_j, self.ftcomp = npts, list(bias_j), list(comp_j), ftcomp
        self.n = 6 + 3 * npts + len(self.bias_j) + len(self.comp_j) + (3 if ftcomp else 0)

    def unpack(self, x):
        o = 0
        frame = x[o:o + 6]; o += 6
        P = x[o:o + 3 * self.npts].reshape(self.npts, 3); o += 3 * self.npts
        b = x[o:o + len(self.bias_j)]; o += len(self.bias_j)
        c = x[o:o + len(self.comp_j)]; o += len(self.comp_j)
        k = x[o:o + 3] if self.ftcomp else None
        return frame, P, b, c, k


def predict(spec, x, idx):
    frame, P, b, c, k = spec.unpack(x)
    Rm = Rot.from_rotvec(frame[:3]).as_matrix(); tm = frame[3:]
    out = np.empty((len(idx), spec.npts, 3))
    for r, i in enumerate(idx):
        qa = QR[i].copy()
        for jj, bj in zip(spec.bias_j, b):
            qa[jj] -= bj
        for jj, cj in zip(spec.comp_j, c):
            qa[jj] += cj * TAU[i, jj]
        pin.forwardKinematics(model, data, full_q(qa))
        if spec.ftcomp:
            pin.updateFramePlacement(model, data, FT_LINK)
            Tft = data.oMf[FT_LINK]
            dR = Rot.from_rotvec(k * TAUH[i]).as_matrix()
            T = Tft * pin.SE3(dR, np.zeros(3)) * T_FT_TOOL
        else:
            T = pin.updateFramePlacement(model, data, FT_TOOL)
        pts = (T.rotation @ P.T).T + T.translation
        out[r] = (Rm @ pts.T).T + tm
    return out


def init_x(spec, idx):
    # alternate: rigid frame (Kabsch on tool origins + current marker) <-> marker position (linear LS)
    Ts = []
    for i in idx:
        pin.forwardKinematics(model, data, full_q(QR[i]))
        Ts.append(pin.updateFramePlacement(model, data, FT_TOOL).copy())
    P = np.zeros((spec.npts, 3))
    for it in range(30):
        A = np.concatenate([[T.act(P[k]) for T in Ts] for k in range(spec.npts)])
        B = np.concatenate([Y[idx, k] for k in range(spec.npts)])
        ca, cb = A.mean(0), B.mean(0)
        U, S, Vt = np.linalg.svd((A - ca).T @ (B - cb))
        D = np.diag([1, 1, np.sign(np.linalg.det(Vt.T @ U.T))])
        Rm = Vt.T @ D @ U.T; tm = cb - Rm @ ca
        for k in range(spec.npts):
            M = np.concatenate([Rm @ T.rotation for T in Ts])
            v = np.concatenate([Y[i, k] - tm - Rm @ T.translation for i, T in zip(idx, Ts)])
            P[k] = np.linalg.lstsq(M, v, rcond=None)[0]
    x = np.zeros(spec.n)
    x[:3] = Rot.from_matrix(Rm).as_rotvec(); x[3:6] = tm
    x[6:6 + 3 * spec.npts] = P.ravel()
    return x


def fit(spec, idx, x0=None):
    if x0 is None:
        x0 = init_x(spec, idx)
    Yt = Y[idx, :spec.npts]
    # scale compliance params so that they are O(1) in the optimiser: c in 1e-4 rad/Nm units
    xs = np.ones(spec.n)
    o = 6 + 3 * spec.npts + len(spec.bias_j)
    xs[o:o + len(spec.comp_j)] = 1e-4
    if spec.ftcomp:
        xs[o + len(spec.comp_j):] = 1e-3
    fun = lambda x: (predict(spec, x, idx) - Yt).ravel()
    r = least_squares(fun, x0, x_scale=xs, method='lm', xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=20000)
    return r


def cv(spec):
    errs = np.zeros(N)
    params = []
    for f in range(5):
        te = np.arange(N)[np.arange(N) % 5 == f]
        tr = np.arange(N)[np.arange(N) % 5 != f]
        r = fit(spec, tr)
        pr = predict(spec, r.x, te)[:, 0]
        errs[te] = np.linalg.norm(pr - Y[te, 0], axis=1) * 1e3
        params.append(r.x)
    rfull = fit(spec, np.arange(N))
    trn = np.linalg.norm(predict(spec, rfull.x, np.arange(N))[:, 0] - Y[:, 0], axis=1) * 1e3
    return errs, np.array(params), rfull, trn


BIAS = [2, 3, 4, 5, 6]  # indices into JN: arm_2..arm_6
MODELS = {
    'A1': Spec(1, BIAS, [], False),
    'A4': Spec(4, BIAS, [], False),
    'B1_246': Spec(1, BIAS, [2, 4, 6], False),
    'B4_246': Spec(4, BIAS, [2, 4, 6], False),
    'B1_all': Spec(1, BIAS, [2, 3, 4, 5, 6, 7], False),
    'B4_all': Spec(4, BIAS, [2, 3, 4, 5, 6, 7], False),
    'C1': Spec(1, BIAS, [], True),
    'C4': Spec(4, BIAS, [], True),
    'BC4_246': Spec(4, BIAS, [2, 4, 6], True),
    'BC4_all': Spec(4, BIAS, [2, 3, 4, 5, 6, 7], True),
    'BC1_246': Spec(1, BIAS, [2, 4, 6], True),
}

if __name__ == '__main__':
    print(f'N={N}; hand mass {HAND_M:.3f} kg, COM in wrist_ft_link {HAND_C.round(4)}; links {HAND_LINKS}')
    print('gravity torque ranges (Nm) per joint:')
    for j, n in enumerate(JN):
        print(f'  {n:18s} min {TAU[:, j].min():8.3f} max {TAU[:, j].max():8.3f} std {TAU[:, j].std():7.3f}')
    print('hand torque range (Nm):', TAUH.min(0).round(3), TAUH.max(0).round(3))
    names = sys.argv[1:] or list(MODELS)
    results = {}
    for name in names:
        spec = MODELS[name]
        t0 = time.time()
        errs, P, rfull, trn = cv(spec)
        fr, Pm, b, c, k = spec.unpack(rfull.x)
        res = dict(nparam=spec.n, mean=errs.mean(), rms=np.sqrt((errs ** 2).mean()), worst=errs.max(),
                   worst_row=int(errs.argmax()), train_mean_full=trn.mean(), train_rms_full=np.sqrt((trn**2).mean()),
                   bias_full=dict(zip([JN[j] for j in spec.bias_j], b.tolist())),
                   comp_full=dict(zip([JN[j] for j in spec.comp_j], c.tolist())),
                   ftk_full=(k.tolist() if k is not None else None), errs=errs.tolist())
        o = 6 + 3 * spec.npts + len(spec.bias_j)
        if spec.comp_j:
            cc = P[:, o:o + len(spec.comp_j)]
            res['comp_folds_mean'] = cc.mean(0).tolist(); res['comp_folds_std'] = cc.std(0).tolist()
        if spec.ftcomp:
            kk = P[:, -3:]
            res['ftk_folds_mean'] = kk.mean(0).tolist(); res['ftk_folds_std'] = kk.std(0).tolist()
        results[name] = res
        print(f"{name:8s} p={spec.n:2d} held-out mean {res['mean']:.3f} rms {res['rms']:.3f} worst {res['worst']:.2f} (row {res['worst_row']}) "
              f"| full-fit train mean {res['train_mean_full']:.3f} rms {res['train_rms_full']:.3f}  [{time.time()-t0:.0f}s]")
        if spec.comp_j:
            print('    compliance c (rad/Nm, full fit):', {kk_: f'{v:.2e}' for kk_, v in res['comp_full'].items()})
            print('    folds mean/std:', np.array(res['comp_folds_mean']).round(7), np.array(res['comp_folds_std']).round(7))
        if spec.ftcomp:
            print('    F/T k (rad/Nm, full fit):', np.array(res['ftk_full']).round(6), 'folds std', np.array(res['ftk_folds_std']).round(6))
        sys.stdout.flush()
    tag = '_'.join(names) if sys.argv[1:] else 'all'
    out = os.path.join(os.environ.get('OUT_DIR', tempfile.gettempdir()), f'tiago_compliance_{tag}.json')
    json.dump(results, open(out, 'w'), indent=1)
    print('results written to', out)
