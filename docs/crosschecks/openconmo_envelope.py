"""Cross-check (not part of the pipeline): a plain envelope pipeline from the Python ecosystem
(openConMo) types the fault on every shared recording of the three rigs, beside the project's
training-free `diagnose`.

The peer pipeline, per record (every parameter fixed before the first run, none chosen on labels):
  1. discrete/random separation (DRS) of the raw signal, N = 16384, Delta = 500 (the defaults of
     openConMo's benchmark_method), Parzen windows, one window pair every 100 samples;
  2. openconmo.kurtogram.fast_kurtogram on the random part -> the band of maximum spectral
     kurtosis; nlevel = the deepest level (at most 7, the function's default) whose narrowest band
     fs / 2^(nlevel+1) still holds the envelope band the score needs, 3 x 1.01 x the highest fault
     order + 2 shaft orders (so the 3rd harmonic and its median neighbourhood are inside the
     band-pass's envelope spectrum);
  3. openconmo.utils.bandpass_filter (its FIR, window method) on that band, the first `order`
     output samples (the filter's start-up) dropped, then openconmo.benchmark_methods.envelope =
     the squared envelope spectrum (SES: |Hilbert|^2, one-sided |FFT|/n);
  4. per hypothesis (inner: BPFI, outer: BPFO, ball: the ball-defect rate, 2 x ball spin, CWRU's
     "BSF"), at the speed given with the record (never estimated from the signal), for harmonics
     h = 1, 2, 3: peak = the largest SES value within h*f*(1 +- 1 %) (at least +- 1 bin),
     floor = the median SES within h*f +- 2 shaft orders; score = sum over h of
     10*log10(peak / floor) dB (SES values are squared-envelope quantities, hence 10 log10);
  5. peer type = the hypothesis with the largest score (first of inner, outer, ball on a tie). The
     peer has no "normal" verdict: it types a fault given that the record is faulty, so
     typed_right is scored on faulty records only (normal records are listed with their type).
  Second column set cpw_* (labelled, cheap): openConMo's cepstrum_prewhitening of the whole raw
  record, then `envelope` of the full band (Smith & Randall's method 2), the same score and rule.

What in openConMo 0.0.6 did not work as documented, and what stands in for it:
  - benchmark_methods.DRS is broken: the cross-spectrum is accumulated as X_delayed * conj(X)
    (the conjugate of the Wiener numerator), the filter is then time-flipped and convolved with
    the UNdelayed signal, with no account of the N + Delta samples between the two windows it was
    estimated from. Its "deterministic part" is the periodic content at a wrong phase, so the
    "random part" keeps (and can double) the discrete lines. The package's own unit test
    (tests/test_DRS.py: 400 Hz sine + noise of rms 0.3, asserts rms error < 0.35) fails:
    python3 .../openconmo/tests/test_DRS.py -> 1.039. This script replaces it with a minimal
    faithful substitute, `drs` below: openConMo's estimator unchanged (same segments, Parzen
    window, hop of 100, N, Delta), numerator X * conj(X_delayed) (the Wiener filter from the
    delayed to the current segment), the impulse response centred (fftshift) and applied with the
    delay its segments imply (N/2 + Delta); the first 3N/2 + Delta samples, where the filter has no
    full history, are dropped. The self-check run at the start of every sweep (numbers in the
    .md) measures both on the package's own test signal.
  - fast_kurtogram works (checked on synthetic resonances at 1, 2.5 and 4.2 kHz: the band found
    holds each), but subtracts the mean from its input in place; it is given a copy.
  - utils.bandpass_filter prints six debug lines (including the signal) on every call (silenced
    here), and its default order 200 is too short for the narrow bands a deep kurtogram returns at
    48 kHz (a Hamming-window FIR of 201 taps has a transition band of about 3.3 fs / 201 = 790 Hz,
    wider than a 750 Hz band); the order used is max(200, 2 ceil(8 fs / bandwidth)), a transition
    band of about a fifth of the band.
  - benchmark_methods.envelope (SES) and cepstrum_prewhitening work as documented.

Records and kinematics (orders of the shaft rate; geometry formulas with r = d/D cos(alpha):
FTF = (1-r)/2, BPFO = n/2 (1-r), BPFI = n/2 (1+r), ball-defect = (D/d)(1-r^2); the script checks
that the SKF 6205 values CWRU lists come out of its geometry):
  - CWRU: every .mat under cwru/ (97 normal at 48 kHz, 60 12 kHz and 13 48 kHz drive-end fault
    records), the drive-end channel named in MANIFEST.csv (174.mat holds X173_*, 3001-3008 hold
    X056-X059 / X048-X051), speed = the file's X###RPM when stored, else the load's nominal speed
    (3001-3008); SKF 6205 orders as CWRU lists them (BPFI 5.4152, BPFO 3.5848, FTF 0.39828,
    ball-defect 4.7135) for every record, 3001-3008 too (their NTN-equivalent geometry is not
    given); label and load from MANIFEST.csv, Smith & Randall's grade from
    smith_randall_grades.csv.
  - MFPT: the 14 files, struct `bearing` (gs, sr, rate); NICE bearing n = 8, d = 0.235 in,
    D = 1.245 in, 0 deg; shaft = the stored nominal rate (25 Hz); label from the file name.
  - UESTC: the 32 files Data/*/*.mat (Data, SampleFrequency), speed = the set speed in the name
    (N_1000_1 -> 1000 rpm); UC204-class insert assumed (n = 8, d = 7.938 mm, D = 33.5 mm, 0 deg,
    as the data README says); N/B/I/O -> normal/ball/inner/outer.

Usage: python3 docs/crosschecks/openconmo_envelope.py [--data-dir DIR] [--out DIR] [--strict]
  --data-dir: the folder holding cwru/, mfpt/, uestc/ (default: $HYBRID_FDD_DATA, else
  ../shared/data beside the repository root); --out: default results/diagnosis under the
  repository root. A missing rig folder is skipped with a message (an error with --strict).
  Writes peer_openconmo.csv (one row per record) and peer_openconmo.md (summary, versions,
  parameters); every number in them but the run times is the same on every run.
Run with Python 3.11.7, openconmo 0.0.6, numpy 2.4.6, scipy 1.17.1 (2 shared cores); the numbers
appear in results/diagnosis/peer_openconmo.md (summary, parameters, DRS self-check) and
results/diagnosis/peer_openconmo.csv (every record). Measured 2026-12-06, faults typed right
(peer type | cpw_*):
  CWRU   55/73 (75.3 %) | 61/73 (83.6 %); 12 kHz grade Y 42/44 | 42/44, P 4/6 | 4/6, N 1/10 | 5/10;
         48 kHz 8/13 | 10/13 (97.mat, the one normal record, is typed inner by both)
  MFPT   13/14 | 14/14
  UESTC  11/24 | 11/24 (the set speed is not the running speed, see its README: a +- 1 % window
         at the set speed misses lines that drift further)
  151 s for the 120 records (DRS and the 48 kHz FIRs dominate); DRS self-check: openconmo.DRS
  1.049, substitute 0.053 (noise rms 0.30).
"""
import argparse
import contextlib
import csv
import io
import math
import os
import platform
import re
import sys
import time
from pathlib import Path

import numpy as np
import scipy
import scipy.fft as sfft
import scipy.io as sio
import scipy.signal as ss

import openconmo
import openconmo.utils as ocu
from openconmo.benchmark_methods import DRS as ocm_drs, cepstrum_prewhitening, envelope
from openconmo.kurtogram import fast_kurtogram

try:
    from importlib.metadata import version as _pkg_version
    OPENCONMO_VERSION = _pkg_version('openconmo')
except Exception:  # pragma: no cover
    OPENCONMO_VERSION = getattr(openconmo, '__version__', 'unknown')

REPO = Path(__file__).resolve().parents[2]
RIGS = ('cwru', 'mfpt', 'uestc')
HYPS = ('inner', 'outer', 'ball')          # tie order of the argmax
ORDER_KEY = {'inner': 'bpfi', 'outer': 'bpfo', 'ball': 'ball'}

# Every fixed parameter (written to the .md).
P = {
    'drs_N': 16384,
    'drs_delta': 500,
    'drs_hop': 100,
    'kurtogram_max_nlevel': 7,
    'harmonics': 3,
    'line_window_rel': 0.01,
    'median_halfwidth_orders': 2.0,
    'fir_min_order': 200,
    'fir_taps_per_band': 8,     # order = max(200, 2 ceil(8 fs / bandwidth))
}

CWRU_LISTED = {'bpfi': 5.4152, 'bpfo': 3.5848, 'ftf': 0.39828, 'ball': 4.7135}
IN = 0.0254  # m


def kinematic_orders(n, d, D, alpha_deg=0.0):
    r = d / D * math.cos(math.radians(alpha_deg))
    return {'ftf': 0.5 * (1 - r), 'bpfo': n / 2 * (1 - r), 'bpfi': n / 2 * (1 + r),
            'ball': D / d * (1 - r * r)}


SKF6205 = kinematic_orders(9, 0.3126 * IN, 1.537 * IN)
NICE = kinematic_orders(8, 0.235 * IN, 1.245 * IN)
UC204 = kinematic_orders(8, 7.938e-3, 33.5e-3)
for _k, _v in CWRU_LISTED.items():
    if abs(SKF6205[_k] - _v) > 2e-4 * _v:
        sys.exit(f'SKF 6205 {_k}: geometry gives {SKF6205[_k]:.5f}, CWRU lists {_v}')
for _k, _v in {'bpfo': 3.245, 'bpfi': 4.755, 'ftf': 0.4056}.items():
    if abs(NICE[_k] - _v) > 5e-4 * _v:
        sys.exit(f'NICE {_k}: geometry gives {NICE[_k]:.5f}, the MFPT data lists {_v}')


# ----------------------------------------------------------------------------- the pipeline
def drs(x, N, delta, hop):
    """Discrete/random separation: openConMo's estimator (segments, window, hop) with the
    orientation and alignment corrected (see the module docstring). Returns (random, first)
    where random[first:] is valid."""
    w = ss.windows.parzen(N)
    num = np.zeros(N, complex)
    den = np.zeros(N)
    for k in range(2 * N + delta, len(x), hop):
        X = sfft.fft(x[k - N:k] * w)
        Xd = sfft.fft(x[k - 2 * N - delta:k - N - delta] * w)
        num += X * np.conj(Xd)
        den += (Xd * np.conj(Xd)).real
    h = np.fft.fftshift(sfft.ifft(num / den).real)
    y = ss.fftconvolve(x, h)[:len(x)]
    lag = N // 2 + delta
    det = np.zeros_like(x)
    det[lag:] = y[:len(x) - lag]
    return x - det, 3 * N // 2 + delta


def nlevel_for(fs, fr, orders, n):
    need = (P['harmonics'] * (1 + P['line_window_rel']) * max(orders[ORDER_KEY[h]] for h in HYPS)
            + P['median_halfwidth_orders']) * fr
    cap = min(P['kurtogram_max_nlevel'], int(math.floor(math.log2(n))) - 7)
    lv = 1
    while lv + 1 <= cap and fs / 2 ** (lv + 2) >= need:
        lv += 1
    return lv


def scores(f, X, fr, orders):
    df = f[1] - f[0]
    out = {}
    for hyp in HYPS:
        fo = orders[ORDER_KEY[hyp]] * fr
        s = 0.0
        for h in range(1, P['harmonics'] + 1):
            fh = h * fo
            half = max(P['line_window_rel'] * fh, df)
            peak = X[np.abs(f - fh) <= half].max()
            floor = np.median(X[np.abs(f - fh) <= P['median_halfwidth_orders'] * fr])
            s += 10 * math.log10(peak / floor)
        out[hyp] = s
    return out


def typed(sc):
    return max(HYPS, key=lambda h: (sc[h], -HYPS.index(h)))


def peer(x, fs, fr, orders):
    rnd, first = drs(x, P['drs_N'], P['drs_delta'], P['drs_hop'])
    rnd = rnd[first:]
    nl = nlevel_for(fs, fr, orders, len(rnd))
    _, _, _, fc, bw = fast_kurtogram(rnd.copy(), fs, nlevel=nl)
    order = max(P['fir_min_order'], 2 * math.ceil(P['fir_taps_per_band'] * fs / bw))
    with contextlib.redirect_stdout(io.StringIO()):
        y = ocu.bandpass_filter(rnd, fs, fc, bw, order=order)
    f, X = envelope(y[order:], fs)
    lo, hi = max(fc - bw / 2, 0.0), min(fc + bw / 2, fs / 2)
    return scores(f, X, fr, orders), lo, hi, nl, order


def peer_cpw(x, fs, fr, orders):
    _, y = cepstrum_prewhitening(x, fs)
    f, X = envelope(y, fs)
    return scores(f, X, fr, orders)


def drs_selfcheck():
    """openConMo's own DRS unit-test signal (tests/test_DRS.py, deterministic seed here)."""
    fs, N, delta = 12e3, 8192, 500
    t = np.linspace(0, 10, int(10 * fs))
    rnd = np.random.default_rng(0).normal(0, 0.30, t.size)
    x = np.sin(2 * np.pi * 400 * t) + rnd
    with contextlib.redirect_stderr(io.StringIO()):
        r_ocm, _ = ocm_drs(x, N, delta)
    r_sub, first = drs(x, N, delta, 100)
    rms = lambda a, b: float(np.sqrt(np.mean((a - b) ** 2)))
    return {'openconmo': rms(r_ocm[N + delta:], rnd[N + delta:]),
            'substitute': rms(r_sub[first:], rnd[first:])}


# ----------------------------------------------------------------------------- the records
def load_cwru(root):
    man = {r['file']: r for r in csv.DictReader(open(root / 'MANIFEST.csv'))}
    grades = {r['record']: r['grade'] for r in csv.DictReader(open(root / 'smith_randall_grades.csv'))}
    files = sorted(root.rglob('*.mat'), key=lambda p: (int(p.stem) if p.stem.isdigit() else 10 ** 9, p.stem))
    for p in files:
        if p.name not in man:
            sys.exit(f'cwru: {p} is not in MANIFEST.csv')
        m = man[p.name]
        d = sio.loadmat(p)
        de = m['de_var'] if m['de_var'] in d else None
        if de is None:
            cands = sorted(k for k in d if k.endswith('_DE_time'))
            own = [k for k in cands if k.startswith(f'X{int(p.stem):03d}')]
            if not (own or len(cands) == 1):
                sys.exit(f'cwru: {p.name}: no drive-end channel to pick among {cands}')
            de = (own or cands)[0]
        rpm_vars = sorted(k for k in d if k.endswith('RPM'))
        own = [k for k in rpm_vars if k.startswith(f'X{int(p.stem):03d}')]
        rpm_var = (own or rpm_vars or [None])[0]
        if rpm_var is not None:
            rpm = float(np.asarray(d[rpm_var]).ravel()[0])
            if m['stored_rpm'] and abs(rpm - float(m['stored_rpm'])) > 0.5:
                print(f'  note: {p.name} stores {rpm} rpm, MANIFEST says {m["stored_rpm"]}')
        else:
            rpm = float(m['nominal_rpm'])
        yield dict(rig='cwru', record=p.stem, label=m['fault'], grade=grades.get(p.stem, ''),
                   fs=float(m['sample_rate_hz']), rpm=rpm, bearing='SKF 6205', orders=CWRU_LISTED,
                   x=np.asarray(d[de], float).ravel())


def load_mfpt(root):
    for p in sorted(root.glob('*.mat')):
        b = sio.loadmat(p, squeeze_me=True, struct_as_record=False)['bearing']
        name = p.stem.lower()
        label = ('inner' if 'innerrace' in name else 'outer' if 'outerrace' in name
                 else 'normal' if 'baseline' in name else None)
        if label is None:
            sys.exit(f'mfpt: no label in the name {p.name}')
        yield dict(rig='mfpt', record=p.stem, label=label, grade='', fs=float(b.sr),
                   rpm=60.0 * float(b.rate), bearing='NICE', orders=NICE,
                   x=np.asarray(b.gs, float).ravel())


def load_uestc(root):
    lab = {'N': 'normal', 'B': 'ball', 'I': 'inner', 'O': 'outer'}
    files = sorted((root / 'Data').glob('*/*.mat'),
                   key=lambda p: (p.stem.split('_')[0], int(p.stem.split('_')[1]), p.stem))
    for p in files:
        m = re.fullmatch(r'([NBIO])_(\d+)_(\d+)', p.stem)
        if not m:
            sys.exit(f'uestc: unexpected file name {p.name}')
        d = sio.loadmat(p, squeeze_me=True)
        yield dict(rig='uestc', record=p.stem, label=lab[m.group(1)], grade='',
                   fs=float(d['SampleFrequency']), rpm=float(m.group(2)), bearing='UC204-class',
                   orders=UC204, x=np.asarray(d['Data'], float).ravel())


LOADERS = {'cwru': load_cwru, 'mfpt': load_mfpt, 'uestc': load_uestc}


# ----------------------------------------------------------------------------- summary
def frac(a, b):
    return f'{a}/{b} ({100 * a / b:.1f} %)' if b else '0/0'


def summarise(rows, rigs, cpw):
    lines = []
    tag = 'cpw_' if cpw else ''
    lines.append('| rig | records | faults typed right | normal records (typed as) |'
                 + ('' if cpw else ' run time (s) |'))
    lines.append('|---|---:|---|---|' + ('' if cpw else '---:|'))
    for rig in rigs:
        rr = [r for r in rows if r['rig'] == rig]
        fa = [r for r in rr if r['label'] != 'normal']
        ok = sum(r[tag + 'typed_right'] == 'true' for r in fa)
        no = [r[tag + 'type'] if cpw else r['peer_type'] for r in rr if r['label'] == 'normal']
        nt = ', '.join(f'{h} {no.count(h)}' for h in HYPS if no.count(h)) or '-'
        lines.append(f'| {rig} | {len(rr)} | {frac(ok, len(fa))} | {len(no)}: {nt} |'
                     + ('' if cpw else f' {sum(r["_sec"] for r in rr):.1f} |'))
    fa = [r for r in rows if r['label'] != 'normal']
    lines.append(f'| all | {len(rows)} | {frac(sum(r[tag + "typed_right"] == "true" for r in fa), len(fa))} '
                 f'| |' + ('' if cpw else f' {sum(r["_sec"] for r in rows):.1f} |'))
    cw = [r for r in rows if r['rig'] == 'cwru' and r['label'] != 'normal']
    if cw:
        lines.append('')
        lines.append('| CWRU subset | faults typed right |')
        lines.append('|---|---|')
        for name, sel in (('12 kHz DE, grade Y', lambda r: r['grade'] == 'Y'),
                          ('12 kHz DE, grade P', lambda r: r['grade'] == 'P'),
                          ('12 kHz DE, grade N', lambda r: r['grade'] == 'N'),
                          ('12 kHz DE, all', lambda r: r['fs_hz'] == '12000'),
                          ('48 kHz DE, 0 hp', lambda r: r['fs_hz'] == '48000')):
            s = [r for r in cw if sel(r)]
            lines.append(f'| {name} ({len(s)}) | {frac(sum(r[tag + "typed_right"] == "true" for r in s), len(s))} |')
    lines.append('')
    lines.append('| rig | label | records | typed inner | typed outer | typed ball |')
    lines.append('|---|---|---:|---:|---:|---:|')
    for rig in rigs:
        for lab in ('normal',) + HYPS:
            s = [r for r in rows if r['rig'] == rig and r['label'] == lab]
            if s:
                ty = [r[tag + 'type'] if cpw else r['peer_type'] for r in s]
                lines.append(f'| {rig} | {lab} | {len(s)} | ' + ' | '.join(str(ty.count(h)) for h in HYPS) + ' |')
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    env = os.environ.get('HYBRID_FDD_DATA')
    ap.add_argument('--data-dir', default=env if env else str(REPO.parent / 'shared' / 'data'))
    ap.add_argument('--out', default=str(REPO / 'results' / 'diagnosis'))
    ap.add_argument('--strict', action='store_true', help='a missing rig folder is an error')
    a = ap.parse_args()
    data = Path(a.data_dir)
    if not data.is_dir():
        sys.exit(f'data directory {data} does not exist (set --data-dir or HYBRID_FDD_DATA to the '
                 f'folder that holds cwru/, mfpt/, uestc/)')
    rigs = []
    for rig in RIGS:
        if (data / rig).is_dir():
            rigs.append(rig)
        elif a.strict:
            sys.exit(f'rig folder {data / rig} is missing (--strict)')
        else:
            print(f'skipping {rig}: {data / rig} is missing')
    if not rigs:
        sys.exit(f'no rig folder (cwru/, mfpt/, uestc/) under {data}')

    check = drs_selfcheck()
    print(f'DRS self-check on openConMo\'s test signal (rms error of the random part, noise rms 0.30): '
          f'openconmo.DRS {check["openconmo"]:.3f}, substitute {check["substitute"]:.3f}')

    rows = []
    t_all = time.perf_counter()
    for rig in rigs:
        for rec in LOADERS[rig](data / rig):
            t0 = time.perf_counter()
            fr = rec['rpm'] / 60.0
            sc, lo, hi, nl, order = peer(rec['x'], rec['fs'], fr, rec['orders'])
            cs = peer_cpw(rec['x'], rec['fs'], fr, rec['orders'])
            sec = time.perf_counter() - t0
            pt, ct = typed(sc), typed(cs)
            faulty = rec['label'] != 'normal'
            row = {
                'rig': rig, 'record': rec['record'], 'label': rec['label'], 'grade': rec['grade'],
                'fs_hz': f'{rec["fs"]:.0f}', 'rpm_nominal': f'{rec["rpm"]:.0f}',
                'bearing': rec['bearing'], 'band_low_hz': f'{lo:.3f}', 'band_high_hz': f'{hi:.3f}',
                'score_inner_db': f'{sc["inner"]:.3f}', 'score_outer_db': f'{sc["outer"]:.3f}',
                'score_ball_db': f'{sc["ball"]:.3f}', 'peer_type': pt,
                'typed_right': (('true' if pt == rec['label'] else 'false') if faulty else ''),
                'seconds': f'{sec:.2f}', 'kurtogram_nlevel': str(nl), 'fir_order': str(order),
                'cpw_inner_db': f'{cs["inner"]:.3f}', 'cpw_outer_db': f'{cs["outer"]:.3f}',
                'cpw_ball_db': f'{cs["ball"]:.3f}', 'cpw_type': ct,
                'cpw_typed_right': (('true' if ct == rec['label'] else 'false') if faulty else ''),
                '_sec': sec,
            }
            rows.append(row)
            print(f'{rig:5s} {rec["record"]:36s} {rec["label"]:6s} {rec["grade"] or "-"} '
                  f'band {lo:7.0f}-{hi:7.0f} Hz  i/o/b {sc["inner"]:7.2f} {sc["outer"]:7.2f} '
                  f'{sc["ball"]:7.2f} -> {pt:5s} {row["typed_right"] or "":5s} '
                  f'(cpw {ct}) {sec:.1f} s', flush=True)
    total = time.perf_counter() - t_all

    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    cols = [k for k in rows[0] if not k.startswith('_')]
    with open(out / 'peer_openconmo.csv', 'w', newline='') as fh:
        w = csv.DictWriter(fh, fieldnames=cols, lineterminator='\n', extrasaction='ignore')
        w.writeheader()
        w.writerows(rows)

    main_tab = summarise(rows, rigs, False)
    cpw_tab = summarise(rows, rigs, True)
    print()
    print('\n'.join(main_tab))
    print()
    print('cpw_* (cepstrum pre-whitening + full-band SES):')
    print('\n'.join(cpw_tab))
    print(f'\ntotal run time {total:.1f} s for {len(rows)} records')

    md = ['# Peer pipeline (openConMo DRS -> fast kurtogram -> SES) on every shared recording', '',
          'generated by python docs/crosschecks/openconmo_envelope.py; do not edit', '',
          f'Python {platform.python_version()}, openconmo {OPENCONMO_VERSION}, numpy {np.__version__}, '
          f'scipy {scipy.__version__}. Rigs: {", ".join(rigs)}. Every number below but the run '
          'times is the same on every run. Per-record numbers: `peer_openconmo.csv` '
          '(`rpm_nominal` is the speed the scores used: CWRU the stored X###RPM, else the load\'s '
          'nominal speed; MFPT the stored nominal 25 Hz; UESTC the set speed).', '',
          '## Pipeline and fixed parameters', '',
          f'1. Discrete/random separation, N = {P["drs_N"]}, Delta = {P["drs_delta"]}, Parzen windows, '
          f'hop {P["drs_hop"]}: openConMo\'s estimator with the cross-spectrum orientation and the '
          'filter alignment corrected (openconmo.benchmark_methods.DRS 0.0.6 does not separate; see '
          'the self-check below and the script\'s docstring); the first 3N/2 + Delta samples dropped.',
          '2. `openconmo.kurtogram.fast_kurtogram` on the random part; nlevel = the deepest level '
          f'(<= {P["kurtogram_max_nlevel"]}) whose narrowest band fs/2^(nlevel+1) >= '
          f'({P["harmonics"]} x {1 + P["line_window_rel"]:.2f} x highest fault order + '
          f'{P["median_halfwidth_orders"]:g}) x shaft rate; band = fc +- bandwidth/2 of the maximum.',
          f'3. `openconmo.utils.bandpass_filter` on that band, order max({P["fir_min_order"]}, '
          f'2 ceil({P["fir_taps_per_band"]} fs / bandwidth)), its first `order` output samples dropped; '
          '`openconmo.benchmark_methods.envelope` (squared envelope spectrum).',
          f'4. Score per hypothesis: sum over harmonics 1..{P["harmonics"]} of 10 log10(max SES within '
          f'h f (1 +- {P["line_window_rel"] * 100:g} %), at least +- 1 bin / median SES within h f +- '
          f'{P["median_halfwidth_orders"]:g} shaft orders), f at the record\'s given speed.',
          '5. Peer type = argmax of the three scores (tie order inner, outer, ball); no normal verdict, '
          'so "typed right" counts faulty records only.',
          '6. cpw_* columns: `openconmo.benchmark_methods.cepstrum_prewhitening` of the whole raw record, '
          '`envelope` of the full band, the same score and rule (Smith & Randall\'s method 2).', '',
          '| bearing | FTF | BPFO | BPFI | ball-defect (2 x BSF) | used for |',
          '|---|---:|---:|---:|---:|---|',
          f'| SKF 6205 (n 9, d 0.3126 in, D 1.537 in, 0 deg), geometry | {SKF6205["ftf"]:.5f} | '
          f'{SKF6205["bpfo"]:.5f} | {SKF6205["bpfi"]:.5f} | {SKF6205["ball"]:.5f} | check only |',
          f'| SKF 6205, CWRU\'s table | {CWRU_LISTED["ftf"]} | {CWRU_LISTED["bpfo"]} | '
          f'{CWRU_LISTED["bpfi"]} | {CWRU_LISTED["ball"]} | every CWRU record |',
          f'| NICE (n 8, d 0.235 in, D 1.245 in, 0 deg) | {NICE["ftf"]:.5f} | {NICE["bpfo"]:.5f} | '
          f'{NICE["bpfi"]:.5f} | {NICE["ball"]:.5f} | MFPT |',
          f'| UC204-class, assumed (n 8, d 7.938 mm, D 33.5 mm, 0 deg) | {UC204["ftf"]:.5f} | '
          f'{UC204["bpfo"]:.5f} | {UC204["bpfi"]:.5f} | {UC204["ball"]:.5f} | UESTC |', '',
          '## DRS self-check', '',
          'openConMo\'s own DRS test signal (tests/test_DRS.py: 10 s at 12 kHz, 400 Hz sine + Gaussian '
          'noise of rms 0.30, N = 8192, Delta = 500; seed fixed here). RMS error of the random part '
          'against the true noise (the package\'s test asserts < 0.35):', '',
          f'- `openconmo.benchmark_methods.DRS`: {check["openconmo"]:.3f}',
          f'- substitute used here: {check["substitute"]:.3f}', '',
          '## Peer type (DRS -> kurtogram band -> SES)', ''] + main_tab + [
          '', '## cpw_*: cepstrum pre-whitening + full-band SES', ''] + cpw_tab + [
          '', f'Run time: {total:.1f} s for {len(rows)} records (2 shared cores; a record\'s `seconds` '
          'covers both variants, not the file loading).', '']
    (out / 'peer_openconmo.md').write_text('\n'.join(md))
    print(f'wrote {out / "peer_openconmo.csv"} and {out / "peer_openconmo.md"}')


if __name__ == '__main__':
    main()
