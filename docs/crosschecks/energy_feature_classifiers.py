"""Cross-check (not part of the pipeline): does a healthy-model residual help the single
window-energy feature, and does the classifier decide it?

Table 4.2's cells (CWRU 12 kHz drive end, 0 hp; normal = 97.mat decimated 48 -> 12 kHz, its first
second fits the predictors and is not scored; 400 windows of 300 samples per record), window
energy sum(r^2) of the raw signal, of the one-step residual of an ARX-Laguerre predictor
(N_a = 16, zeta = -0.2259, the pipeline's choice on 97) and of an AR(16) predictor, both fitted
on that first second. Two classifiers on the one feature, random 75/25 split per class, 3 seeds:
  - per-pair minimum-error threshold, one-vs-one vote;
  - a soft-margin linear SVM as the `classify` crate's default (per-pair standardisation,
    balanced weights, C = 10, hinge loss; solved by Nelder-Mead on (w, b) in 1-D).
Usage: python3 docs/crosschecks/energy_feature_classifiers.py [DATA_DIR]  (default ../shared/data)
Measured 2026-11-25 (mean over the three crack sizes, %):
  raw       thresholds 81.4   linear SVM 79.5
  Laguerre  thresholds 85.1   linear SVM 80.7
  AR(16)    thresholds 86.9   linear SVM 82.1
"""
import csv, sys
import numpy as np, scipy.io as sio, scipy.signal as ss
from scipy.optimize import minimize

D = (sys.argv[1] if len(sys.argv) > 1 else '../shared/data') + '/cwru/'
man = {r['file']: r for r in csv.DictReader(open(D + 'MANIFEST.csv'))}

def load(f):
    r = man[f]; x = sio.loadmat(D + r['rel_path'])[r['de_var']].ravel().astype(float)
    return ss.decimate(x, 4, ftype='fir') if int(r['sample_rate_hz']) == 48000 else x

def ar_residual(y, fit, p):
    n = len(fit); X = np.column_stack([fit[p - i - 1:n - i - 1] for i in range(p)])
    a, *_ = np.linalg.lstsq(X, fit[p:], rcond=None)
    return y - ss.lfilter(np.r_[0, a], [1], y)

def bank(y, z, n):
    g = np.sqrt(1 - z * z); s = ss.lfilter([0, g], [1, -z], y); out = [s]
    for _ in range(1, n):
        s = ss.lfilter([-z, 1], [1, -z], s); out.append(s)
    return np.column_stack(out)

def laguerre_residual(y, fit, z, n):
    X = bank(fit, z, n); k, *_ = np.linalg.lstsq(X[50:], fit[50:], rcond=None)
    return y - bank(y, z, n) @ k

def energies(r, off, L=300, n=400):
    r = r[off:]; k = min(n, len(r) // L); return (r[:k * L].reshape(k, L) ** 2).sum(1)

def threshold_pair(a, b):
    v = np.r_[a, b]; lab = np.r_[np.zeros(len(a)), np.ones(len(b))]; best = (1e9, 0, 0)
    for t in np.unique(v):
        for s in (0, 1):
            e = (((v > t) if s == 0 else (v <= t)) != lab).sum()
            if e < best[0]: best = (e, t, s)
    _, t, s = best
    return lambda x: (x > t) if s == 0 else (x <= t)

def svm_pair(a, b, C=10.0):
    v = np.r_[a, b]; mu, sd = v.mean(), v.std(); v = (v - mu) / sd
    lab = np.r_[-np.ones(len(a)), np.ones(len(b))]
    wt = np.r_[np.full(len(a), len(v) / (2 * len(a))), np.full(len(b), len(v) / (2 * len(b)))]
    f = lambda p: 0.5 * p[0] ** 2 + C * np.sum(wt * np.maximum(0, 1 - lab * (p[0] * v + p[1])))
    r = min((minimize(f, [w0, 0.0], method='Nelder-Mead',
                      options={'xatol': 1e-6, 'fatol': 1e-8, 'maxiter': 4000}) for w0 in (1.0, -1.0)),
            key=lambda r: r.fun)
    w, b0 = r.x
    return lambda x: (w * (x - mu) / sd + b0) > 0

def accuracy(feats, pair):
    X = np.concatenate(feats); y = np.concatenate([np.full(len(f), i) for i, f in enumerate(feats)])
    acc = []
    for seed in range(3):
        rng = np.random.default_rng(seed); tr = []; te = []
        for c in range(len(feats)):
            idx = np.where(y == c)[0]; rng.shuffle(idx); k = int(.75 * len(idx))
            tr += list(idx[:k]); te += list(idx[k:])
        tr = np.array(tr); te = np.array(te); votes = np.zeros((len(te), len(feats)))
        for i in range(len(feats)):
            for j in range(i + 1, len(feats)):
                p = pair(X[tr][y[tr] == i], X[tr][y[tr] == j])(X[te])
                votes[~p, i] += 1; votes[p, j] += 1
        acc.append((votes.argmax(1) == y[te]).mean())
    return 100 * np.mean(acc)

h = load('97.mat'); fit = h[:12000]
cells = [['118.mat', '130.mat', '105.mat'], ['185.mat', '197.mat', '169.mat'], ['222.mat', '234.mat', '209.mat']]
recs = {f: load(f) for c in cells for f in c}
for name, res in [('raw', lambda y: y), ('Laguerre', lambda y: laguerre_residual(y, fit, -0.2259, 16)),
                  ('AR(16)', lambda y: ar_residual(y, fit, 16))]:
    hr = res(h)
    out = {}
    for cname, pair in [('thresholds', threshold_pair), ('linear SVM', svm_pair)]:
        out[cname] = np.mean([accuracy([energies(hr, 12000)] + [energies(res(recs[f]), 0) for f in c], pair)
                              for c in cells])
    print(f"{name:9} thresholds {out['thresholds']:.1f}   linear SVM {out['linear SVM']:.1f}", flush=True)
