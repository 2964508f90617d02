"""Cross-check (not part of the pipeline): does a generalised orthonormal basis with poles taken
from an AR model of the healthy fit segment predict better than the Laguerre basis (issue 14,
held-out NRMSE target <= 0.30)?

Same segment and scoring as prediction_floor.py: the first 1 s of 97.mat's drive-end channel,
decimated by 4 to 12 kHz, fitted on the first 70 %, scored on the last 30 %. Poles: the roots of
an AR(p) model fitted on the first 70 %, one of each conjugate pair, each used once or twice
(Takenaka-Malmquist functions, real and imaginary parts as regressors).

Usage: python3 docs/crosschecks/gob_basis.py [DATA_DIR]  (default ../shared/data)
Measured 2026-11-27 (functions: NRMSE): 16: 0.528, 24: 0.457, 32: 0.446, 34: 0.433, 48: 0.407 /
0.408, 64: 0.359, 68: 0.373, 96: 0.351, 128: 0.326; Laguerre of the same size (prediction_floor.py)
0.392 / 0.365 / 0.332 / 0.302 at 16 / 32 / 64 / 128. Not better; not built.
"""
import csv, sys
import numpy as np, scipy.io as sio, scipy.signal as ss
D=(sys.argv[1] if len(sys.argv) > 1 else '../shared/data') + '/cwru/'
man={r['file']:r for r in csv.DictReader(open(D+'MANIFEST.csv'))}
r=man['97.mat']; x=sio.loadmat(D+r['rel_path'])[r['de_var']].ravel().astype(float)
taps,beta=ss.kaiserord(80.0,(6000.0-4800.0)/24000.0)
h=ss.firwin(taps,5400.0,window=('kaiser',beta),fs=48000.0)
full=ss.lfilter(h,1.0,x)[taps:][::4]
y=full[:12000]-full[:12000].mean(); nfit=int(round(0.7*len(y)))
def nrmse(e,t): return np.linalg.norm(e)/np.linalg.norm(t-t.mean())
def arpoles(p):
    X=np.column_stack([y[p-k-1:nfit-k-1] for k in range(p)]); t=y[p:nfit]
    th,*_=np.linalg.lstsq(X,t,rcond=None)
    return np.roots(np.r_[1,-th])
def gob(poles, warm=300):
    # Takenaka-Malmquist basis, complex; regressors real+imag parts
    cols=[]; s=y.astype(complex)
    # first: delayed through 1/(q-xi)
    prev_allpass=s
    for i,xi in enumerate(poles):
        g=np.sqrt(1-abs(xi)**2)
        b=ss.lfilter([0,g],[1,-xi],prev_allpass)
        cols.append(b)
        # all-pass (1 - conj(xi) q)/(q - xi) = (-conj(xi) + q^-1 ... ) in q^-1: (q^-1 - conj xi)/(1 - xi q^-1)
        prev_allpass=ss.lfilter([-np.conj(xi),1],[1,-xi],prev_allpass)
    X=[]
    for c in cols:
        X.append(c.real)
        if np.max(abs(c.imag))>1e-12*np.max(abs(c.real)+1e-300): X.append(c.imag)
    X=np.column_stack(X)
    k,*_=np.linalg.lstsq(X[warm:nfit],y[warm:nfit],rcond=None)
    return nrmse(y[nfit:]-X[nfit:]@k,y[nfit:]), X.shape[1]
for p in (16,24,32,48,64):
    rts=arpoles(p)
    # one of each conj pair (imag>=0)
    sel=rts[rts.imag>=-1e-12]
    sel=sel[np.argsort(-abs(sel))]
    for reps in (1,2):
        e,n=gob(np.tile(sel,reps))
        print(f'AR({p}) poles, {len(sel)} distinct x{reps}: {n} functions, NRMSE {e:.3f}')
