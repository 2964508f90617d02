"""Black-box check of `hybrid-fdd close-loop` (issue 11; not part of the pipeline or the tests).

Adds known effects to measured CWRU drive-end recordings, runs the command as a user would,
from the rig's machine model (`results/close-loop/rig-{12k,48k}.json`, mains 60 Hz, the CLI's
default), and prints what the loop names beside the truth. The untouched record's entry in
`results/close-loop/<n>.json` (from `cargo xtask close-loop --all-real`) is the control.
Findings and fixes: docs/equations/close-loop.md, "A second black-box check" (cases A-Y) and
"A third black-box check" (cases a-q, on records neither the tests nor the earlier cases use),
"A fourth black-box check" (r-z) and "A fifth black-box check" (`--random SEED`: seeded random
effects, one kind per record in turn, each judged against the same record run untouched).

Usage (after `cargo build --release -p hybrid-fdd-cli`, from the repository root; needs numpy
and scipy):
    python3 docs/crosschecks/close_loop_blackbox.py [CASE ...]   (default: every case)
    python3 docs/crosschecks/close_loop_blackbox.py --random SEED [48k]  (fifth round: random effects)
Data: $HYBRID_FDD_DATA or ../shared/data. Work files go to /tmp/close_loop_blackbox.

Amplitudes are fractions of the record's RMS (a tone of fraction q has amplitude q*sqrt(2)*RMS).
Two cases are test-design limits, not loop errors: D (a half order of 1796 rpm, 14.97 Hz, beside
a 15 Hz tone on a 10 s record, 0.1 Hz bins: one line) and Y (a mains comb resampled with the
record, so it sits on 2 x fr: named as the shaft comb it then is). In the third round, c modulates
the record's DC offset too (a line at exactly the cage rate), d's "mode" with a negative gain is
a bump at 2609 Hz, not a notch, and f's 3300 Hz tone lands 2 Hz from the fault's own sideband
20 x BPFI + 2 x fr.
"""
import csv
import json
import os
import subprocess
import sys

import numpy as np
import scipy.io as sio
import scipy.signal as ss

DATA = os.environ.get("HYBRID_FDD_DATA", "../shared/data") + "/cwru/"
WORK = "/tmp/close_loop_blackbox"
CLI = "./target/release/hybrid-fdd"
MAN = {r["file"]: r for r in csv.DictReader(open(DATA + "MANIFEST.csv"))}


def load(n):
    r = MAN[f"{n}.mat"]
    m = sio.loadmat(DATA + r["rel_path"])
    y = m[r["de_var"]].ravel().astype(float)
    return y, float(r["sample_rate_hz"]), float(r["stored_rpm"] or r["nominal_rpm"])


def tone(y, fs, f, frac, ph=0.3):
    t = np.arange(len(y)) / fs
    a = frac * np.std(y) * np.sqrt(2)
    return y + a * np.sin(2 * np.pi * f * t + ph), a


def am(y, fs, fm, mu, ph=0.0):
    t = np.arange(len(y)) / fs
    return y * (1 + mu * np.cos(2 * np.pi * fm * t + ph))


def mode(y, fs, f0, z, c):
    w = 2 * np.pi * f0 / fs
    r = np.exp(-z * w)
    x = ss.lfilter([1], [1, -2 * r * np.cos(w * np.sqrt(1 - z * z)), r * r], y)
    return y + x / np.std(x) * np.std(y) * c


def faster(y, s):
    """Play `y` s times faster: band-limited resampling by the ratio nearest 1/s with a
    denominator up to 2000 (until 2026-11-26 linear interpolation, whose gain ripples at the
    rate the fractional position wraps: sidebands at fs*|1 - s| around every high line)."""
    from fractions import Fraction
    r = Fraction(1 / s).limit_denominator(2000)
    return ss.resample_poly(y, r.numerator, r.denominator)


def case(c):
    """(record, fault, size in, signal, fs, rpm, truth) of one case."""
    if c == "A":
        y, fs, rpm = load(144)
        return 144, "outer", 0.007, am(y, fs, rpm / 60, 0.3), fs, rpm, "AM 30 % at fr"
    if c == "B":
        y, fs, rpm = load(199)
        return 199, "outer", 0.014, mode(y, fs, 1900, 0.02, 0.5), fs, rpm, "mode 1900 Hz"
    if c == "C":
        y, fs, rpm = load(171)
        y2, a4 = tone(y, fs, 4 * rpm / 60, 0.25)
        y2, a = tone(y2, fs, 1234, 0.25)
        t = f"4x {a4:.4f}, tone 1246.34 Hz {a:.4f}, speed x1.01"
        return 171, "inner", 0.014, faster(y2, 1.01), fs, rpm, t
    if c == "D":
        y, fs, rpm = load(250)
        y2, a1 = tone(y, fs, 0.5 * rpm / 60, 0.25)
        y2, a2 = tone(y2, fs, 15, 0.25)
        return 250, "outer", 0.021, y2, fs, rpm, f"0.5x {a1:.4f}, 15 Hz {a2:.4f}"
    if c == "E":
        y, fs, rpm = load(186)
        y2, a = tone(y, fs, 5 * rpm / 60, 0.3)
        return 186, "ball", 0.014, y2, fs, rpm, f"5x {a:.4f}"
    if c == "F":
        y, fs, rpm = load(3002)
        y2, a = tone(y, fs, 4400, 0.25)
        return 3002, "inner", 0.028, y2, fs, rpm, f"4400 Hz {a:.4f}"
    if c == "G":
        y, fs, rpm = load(246)
        for k in (1, 2, 3, 4):
            y, a = tone(y, fs, 60 * k, 0.12, ph=0.7 * k)
        return 246, "outer", 0.021, y, fs, rpm, f"60 Hz comb, 4 lines, {a:.4f}"
    if c == "H":
        y, fs, rpm = load(97)
        return 97, "none", 0, am(y, fs, rpm / 60, 0.25), fs, rpm, "AM 25 % at fr"
    if c == "I":
        y, fs, rpm = load(209)
        return 209, "inner", 0.021, am(y, fs, rpm / 60, 0.3), fs, rpm, "AM 30 % at fr"
    if c == "J":
        y, fs, rpm = load(201)
        return 201, "outer", 0.014, mode(y, fs, 7000, 0.015, 0.5), fs, rpm, "mode 7000 Hz"
    if c == "N":
        y, fs, rpm = load(238)
        y2, a = tone(y, fs, 3 * rpm / 60, 0.25)
        return 238, "outer", 0.021, faster(y2, 0.98), fs, rpm, f"3x {a:.4f}, speed x0.98"
    if c == "P":
        y, fs, rpm = load(97)
        y, fs = ss.resample_poly(y, 1, 4), 12000.0
        y, a1 = tone(y, fs, 1.5 * rpm / 60, 0.25)
        y, a2 = tone(y, fs, 800, 0.2)
        y, a3 = tone(y, fs, 2500, 0.2)
        return 97, "none", 0, y, fs, rpm, f"1.5x {a1:.4f}, 800 Hz {a2:.4f}, 2500 Hz {a3:.4f}"
    if c == "R":
        y, fs, rpm = load(160)
        fr = rpm / 60
        y2, a = tone(am(y, fs, 0.39828 * fr, 0.3, np.pi / 2), fs, 2 * fr, 0.2)
        return 160, "outer", 0.007, y2, fs, rpm, f"cage AM 30 %, 2x {a:.4f}"
    if c == "U":
        y, fs, rpm = load(109)
        y2, a = tone(y, fs, 21000, 0.25)
        return 109, "inner", 0.007, y2, fs, rpm, f"21000 Hz {a:.4f}"
    if c == "V":
        y, fs, rpm = load(109)
        y2, a = tone(y, fs, 37, 0.2)
        return 109, "inner", 0.007, y2, fs, rpm, f"37 Hz {a:.4f}"
    if c == "X":
        y, fs, rpm = load(224)
        y2, a = tone(y, fs, 5300, 0.25)
        return 224, "ball", 0.021, y2, fs, rpm, f"5300 Hz {a:.4f}"
    if c == "Y":
        y, fs, rpm = load(262)
        for k in (1, 2, 3):
            y, a = tone(y, fs, 60 * k, 0.12, ph=0.7 * k)
        return 262, "outer", 0.021, faster(y, 1.015), fs, rpm, "60 Hz comb, speed x1.015"
    # third round (2026-11-26, "A third black-box check"): lower-case letters
    if c == "a":
        y, fs, rpm = load(107)
        y2, a = tone(y, fs, 12, 0.25)
        return 107, "inner", 0.007, y2, fs, rpm, f"12 Hz {a:.4f}"
    if c == "b":
        y, fs, rpm = load(135)
        y2, a1 = tone(y, fs, 2.5 * rpm / 60, 0.2)
        y2, a2 = tone(y2, fs, 9000, 0.15)
        return 135, "outer", 0.007, y2, fs, rpm, f"2.5x {a1:.4f}, 9000 Hz {a2:.4f}"
    if c == "c":
        y, fs, rpm = load(97)
        y, fs = ss.resample_poly(y, 1, 4), 12000.0
        fc = 0.39828 * rpm / 60
        return 97, "none", 0, am(y, fs, fc, 0.3), fs, rpm, f"AM 30 % at the cage rate {fc:.3f} Hz"
    if c == "d":
        y, fs, rpm = load(97)
        y, fs = ss.resample_poly(y, 1, 4), 12000.0
        return 97, "none", 0, mode(y, fs, 2600, 0.02, -0.4), fs, rpm, "mode 2600 Hz, gain -0.4"
    if c == "e":
        y, fs, rpm = load(147)
        y2, a1 = tone(y, fs, 5400, 0.25)
        y2, a2 = tone(y2, fs, rpm / 60, 0.25)
        return 147, "outer", 0.007, y2, fs, rpm, f"5400 Hz {a1:.4f}, 1x {a2:.4f}"
    if c == "f":
        y, fs, rpm = load(174)
        y2, a1 = tone(y, fs, 150, 0.15)
        y2, a2 = tone(y2, fs, 3300, 0.15)
        y2, a3 = tone(y2, fs, 15000, 0.15)
        t = f"150 {a1:.4f}, 3300 {a2:.4f}, 15000 Hz {a3:.4f} (x1/0.993 after resampling), speed x0.993"
        return 174, "inner", 0.014, faster(y2, 0.993), fs, rpm, t
    if c == "g":
        y, fs, rpm = load(189)
        for k in (1, 2, 3, 4):
            y, a = tone(y, fs, 50 * k, 0.12, ph=0.7 * k)
        return 189, "ball", 0.014, y, fs, rpm, f"50 Hz comb, 4 lines, {a:.4f} (--line-frequency 50)"
    if c == "h":
        y, fs, rpm = load(258)
        y2, a = tone(y, fs, 0.5 * rpm / 60, 0.25)
        return 258, "outer", 0.021, y2, fs, rpm, f"0.5x {a:.4f}"
    if c == "i":
        y, fs, rpm = load(3006)
        y2, a = tone(am(y, fs, rpm / 60, 0.2), fs, 250, 0.3)
        return 3006, "ball", 0.028, y2, fs, rpm, f"AM 20 % at fr, 250 Hz {a:.4f}"
    if c == "j":
        y, fs, rpm = load(211)
        y2, a = tone(y, fs, 2 * rpm / 60, 0.3)
        return 211, "inner", 0.021, faster(y2, 1.012), fs, rpm, f"2x {a:.4f}, speed x1.012"
    if c == "k":
        y, fs, rpm = load(122)
        return 122, "ball", 0.007, mode(y, fs, 11000, 0.015, 1.0), fs, rpm, "mode 11000 Hz"
    if c == "l":
        y, fs, rpm = load(236)
        for k in (1, 2, 3, 4, 5):
            y, a = tone(y, fs, 60 * k, 0.1, ph=0.7 * k)
        return 236, "outer", 0.021, y, fs, rpm, f"60 Hz comb, 5 lines, {a:.4f}"
    if c == "m":
        y, fs, rpm = load(226)
        y2, a = tone(y, fs, 0.45 * fs, 0.2)
        return 226, "ball", 0.021, y2, fs, rpm, f"21600 Hz (0.45 fs) {a:.4f}"
    if c == "n":
        y, fs, rpm = load(97)
        y2, a = tone(y, fs, 10, 0.2)
        return 97, "none", 0, y2, fs, rpm, f"10 Hz {a:.4f}"
    if c == "q":
        y, fs, rpm = load(3001)
        y2, a1 = tone(y, fs, 5000, 0.10)
        y2, a2 = tone(y2, fs, 4 * rpm / 60, 0.15)
        return 3001, "inner", 0.028, y2, fs, rpm, f"5000 Hz {a1:.4f}, 4x {a2:.4f}"
    if c == "o":
        y, fs, rpm = load(148)
        y2, a1 = tone(y, fs, 12000, 0.10)
        y2, a2 = tone(y2, fs, 1.5 * rpm / 60, 0.15)
        return 148, "outer", 0.007, y2, fs, rpm, f"12000 Hz {a1:.4f}, 1.5x {a2:.4f}"
    # fourth round (2026-11-27, "A fourth black-box check"): r-z, records no test or earlier case uses
    if c == "r":
        y, fs, rpm = load(108)
        y2, a1 = tone(y, fs, 640, 0.2)
        y2, a2 = tone(y2, fs, 3 * rpm / 60, 0.15)
        return 108, "inner", 0.007, y2, fs, rpm, f"640 Hz {a1:.4f}, 3x {a2:.4f}"
    if c == "s":
        y, fs, rpm = load(187)
        return 187, "ball", 0.014, mode(y, fs, 3500, 0.02, 0.5), fs, rpm, "mode 3500 Hz"
    if c == "t":
        y, fs, rpm = load(161)
        y2, a = tone(y, fs, 17000, 0.15)
        t = f"17000 Hz {a:.4f} (x1/1.008 after resampling), speed x1.008"
        return 161, "outer", 0.007, faster(y2, 1.008), fs, rpm, t
    if c == "u":
        y, fs, rpm = load(3004)
        y2, a = tone(y, fs, 950, 0.3)
        return 3004, "inner", 0.028, y2, fs, rpm, f"950 Hz {a:.4f}"
    if c == "v":
        y, fs, rpm = load(145)
        y2, a = tone(y, fs, 2 * rpm / 60, 0.25)
        return 145, "outer", 0.007, faster(y2, 0.99), fs, rpm, f"2x {a:.4f}, speed x0.99"
    if c == "w":
        y, fs, rpm = load(259)
        y2, a = tone(y, fs, 2.5 * rpm / 60, 0.2)
        return 259, "outer", 0.021, y2, fs, rpm, f"2.5x {a:.4f}"
    if c == "x":
        y, fs, rpm = load(97)
        y2, a1 = tone(y, fs, 333, 0.1)
        y2, a2 = tone(y2, fs, 4321, 0.1)
        return 97, "none", 0, y2, fs, rpm, f"333 Hz {a1:.4f}, 4321 Hz {a2:.4f}"
    if c == "y":
        y, fs, rpm = load(212)
        for k in (1, 2, 3):
            y, a = tone(y, fs, 60 * k, 0.12, ph=0.7 * k)
        return 212, "inner", 0.021, y, fs, rpm, f"60 Hz comb, 3 lines, {a:.4f}"
    if c == "z":
        y, fs, rpm = load(234)
        fc = 0.39828 * rpm / 60
        return 234, "outer", 0.021, am(y, fs, fc, 0.4), fs, rpm, f"AM 40 % at the cage rate {fc:.3f} Hz"
    raise SystemExit(f"unknown case {c}")


# fifth round (2026-11-28, "A fifth black-box check"): seeded random effects on records no test
# uses, one kind per record in turn, each judged against the same record run untouched
RANDOM_RECORDS = [106, 119, 145, 186, 199, 248, 261, 172, 224, 158, 3002, 132]
# the 48 kHz drive-end records no test uses (`--random SEED 48k`)
RANDOM_RECORDS_48K = [122, 161, 174, 189, 201, 238, 250, 262]
RANDOM_KINDS = ["tone", "order", "half", "am_shaft", "am_cage", "speed", "two_tones"]


def random_case(y, fs, rpm, kind, rng):
    """(signal, truth) of one random case on the record `y`: `truth` holds the kind the loop
    should name (`kind`), the frequency (`f`, Hz), and the amplitude (`a`), depth (`depth`) or
    speed ratio (`ratio`) it should report."""
    fr = rpm / 60
    if kind in ("tone", "two_tones"):
        f = float(np.exp(rng.uniform(np.log(10), np.log(0.45 * fs))))
        y2, a = tone(y, fs, f, rng.uniform(0.3, 0.45), ph=rng.uniform(0, 2 * np.pi))
        truth = [dict(kind="tone", f=f, a=a)]
        if kind == "two_tones":
            f2 = float(np.exp(rng.uniform(np.log(10), np.log(0.45 * fs))))
            y2, a2 = tone(y2, fs, f2, rng.uniform(0.3, 0.45))
            truth.append(dict(kind="tone", f=f2, a=a2))
        return y2, truth
    if kind in ("order", "half"):
        k = int(rng.integers(1, 6)) if kind == "order" else float(rng.choice([0.5, 1.5, 2.5]))
        y2, a = tone(y, fs, k * fr, rng.uniform(0.3, 0.45), ph=1.0)
        return y2, [dict(kind="shaft_harmonic", f=k * fr, a=a)]
    if kind in ("am_shaft", "am_cage"):
        fm = fr if kind == "am_shaft" else 0.39828 * fr
        mu = rng.uniform(0.3, 0.5)
        return am(y, fs, fm, mu), [dict(kind="modulation", f=fm, depth=mu)]
    s = 1 + rng.choice([-1, 1]) * rng.uniform(0.01, 0.03)
    return faster(y, s), [dict(kind="speed", ratio=s)]


def run_loop(path, label, n, fs, rpm):
    """The loop on `path` as a user runs it, from the rig's machine model; its JSON report."""
    r = MAN[f"{n}.mat"]
    fault = {"normal": "none"}.get(r["fault"], r["fault"])
    report = f"{WORK}/{label}.report.json"
    if not os.path.exists(report):
        args = [CLI, "close-loop", "--input", path, "--fs", str(fs), "--rpm", str(rpm),
                "--fault", fault, "--machine",
                "results/close-loop/rig-%s.json" % ("48k" if fs == 48000 else "12k"),
                "--units", "g", "--report", report]
        if fault != "none":
            args += ["--fault-size-in", r["fault_diameter_in"]]
        out = subprocess.run(args, capture_output=True, text=True)
        if out.returncode != 0:
            raise SystemExit(f"{label}: {' '.join(args)}\n{out.stderr}")
    return json.load(open(report))


def named(d, t):
    """The effect of report `d` that names truth `t` (frequency within 0.5 %), or None."""
    for e in d["effects"]:
        if t["kind"] == "speed":
            r = e["parameters"].get("ratio")
            if e["kind"] in ("speed_offset", "defect_rate") and r and abs(r / t["ratio"] - 1) < 0.005:
                return e
        elif e["kind"] == t["kind"] and e["frequency_hz"] and abs(e["frequency_hz"] / t["f"] - 1) < 0.005:
            return e
        elif t["kind"] == "shaft_harmonic" and e["kind"] == "shaft_comb":
            # a comb of shaft orders names its strongest order with that order's amplitude
            p = e["parameters"]
            if abs(p["strongest_order"] * e["frequency_hz"] / t["f"] - 1) < 0.005:
                return dict(e, parameters=dict(p, amplitude=p["strongest_amplitude"]))
    return None


def random_round(seed, records):
    rng = np.random.default_rng(seed)
    for i, n in enumerate(records):
        kind = RANDOM_KINDS[i % len(RANDOM_KINDS)]
        x, fs, rpm = load(n)
        y, truth = random_case(x, fs, rpm, kind, np.random.default_rng(rng.integers(1 << 31)))
        paths = {}
        for label, sig in ((f"{n}_untouched", x), (f"{n}_{kind}_{seed}", y)):
            paths[label] = f"{WORK}/{label}.csv"
            if not os.path.exists(paths[label]):
                np.savetxt(paths[label], sig, fmt="%.9e", header="accel", comments="")
        ctrl, d = (run_loop(p, label, n, fs, rpm) for label, p in paths.items())
        print(f"{n} {kind}: error {d['error_before']:.3f} -> {d['error_after']:.3f} dB")
        for t in truth:
            e, c = named(d, t), named(ctrl, t)
            key = {"tone": "a", "shaft_harmonic": "a", "modulation": "depth", "speed": "ratio"}[t["kind"]]
            got = e and e["parameters"].get({"a": "amplitude"}.get(key, key))
            print(f"   added {t}: named {e['kind'] if e else 'NOT NAMED'}"
                  f"{f' {got:.4g}' if got else ''}{' (also in the untouched record)' if c else ''}")


def main():
    os.makedirs(WORK, exist_ok=True)
    if sys.argv[1:2] == ["--random"]:
        records = RANDOM_RECORDS_48K if sys.argv[3:4] == ["48k"] else RANDOM_RECORDS
        random_round(int(sys.argv[2]) if len(sys.argv) > 2 else 8, records)
        return
    for c in sys.argv[1:] or list("ABCDEFGHIJNPRUVXY"):
        n, fault, size, y, fs, rpm, truth = case(c)
        path = f"{WORK}/{c}{n}.csv"
        with open(path, "w") as f:
            f.write("accel\n" + "\n".join(f"{v:.7g}" for v in y))
        rig = "results/close-loop/rig-%s.json" % ("48k" if fs == 48000 else "12k")
        args = [CLI, "close-loop", "--input", path, "--fs", str(fs), "--rpm", str(rpm),
                "--fault", fault, "--machine", rig, "--units", "g",
                "--report", f"{WORK}/{c}{n}.report.json"]
        if c == "g":
            args += ["--line-frequency", "50"]
        if fault != "none":
            args += ["--fault-size-in", str(size)]
        r = subprocess.run(args, capture_output=True, text=True)
        if r.returncode != 0:
            raise SystemExit(f"{c}: {' '.join(args)}\n{r.stderr}")
        d = json.load(open(f"{WORK}/{c}{n}.report.json"))
        print(f"{c} {n}: added {truth}; error {d['error_before']:.3f} -> {d['error_after']:.3f} dB")
        for e in d["effects"]:
            p = " ".join(f"{k}={v:.4g}" for k, v in e["parameters"].items() if k != "modes")
            print(f"   {e['kind']:16s} {e['frequency_hz'] or 0:10.3f} Hz {e['placement']:11s} {p[:110]}")


if __name__ == "__main__":
    main()
