"""hybrid_fdd in one page, runnable top to bottom (each block a notebook cell).

    python python/examples/quickstart.py [DATA_DIR] [--out DIR]

DATA_DIR holds cwru/ (default: HYBRID_FDD_DATA, else ../shared/data beside the repository).
Writes the overlay figure and the calibrated machine model to --out (default: a temporary
directory).
"""

import os
import sys
import tempfile
import time
from pathlib import Path

import hybrid_fdd as hf

args = [a for a in sys.argv[1:] if not a.startswith("--")]
out = Path(sys.argv[sys.argv.index("--out") + 1]) if "--out" in sys.argv else \
    Path(tempfile.mkdtemp(prefix="hybrid-fdd-quickstart-"))
if args and args[0] == str(out):
    args = args[1:]
out.mkdir(parents=True, exist_ok=True)
data = Path(args[0] if args else os.environ.get(
    "HYBRID_FDD_DATA", Path(__file__).resolve().parents[2].parent / "shared" / "data"))
cwru = data / "cwru"

# %% 1. read a CWRU record: samples as a float64 array, with its rate, speed and unit
rec = hf.read(cwru / "12k_drive_end" / "130.mat")
print(rec)  # Recording('…/130.mat', channel='DE', 121991 samples, fs=12000 Hz, rpm=1796, unit='g')

# %% 2. diagnose it against the healthy record 97 (48 kHz, decimated to 12 kHz on the way)
d = hf.diagnose(rec, bearing="6205", baseline=cwru / "normal" / "97.mat")
print(d)  # <Diagnosis '130.mat': outer (...)>
for name, e in d.evidence.items():
    print(f"  {name:5s} detected={e.detected!s:5s} p_healthy={e.p_healthy:.2g} "
          f"fault line {e.fault_hz:.1f} Hz")

# %% 3. the overlay figure (matplotlib, when installed)
try:
    import matplotlib
    matplotlib.use("Agg")
    ax = d.plot()
    ax.figure.savefig(out / "130_envelope.png", dpi=100)
    print("figure:", out / "130_envelope.png")
except ImportError:
    print("matplotlib not installed: no figure")

# %% 4. calibrate a machine model on the healthy record 97 (48 -> 12 kHz) and save it
rig = hf.calibrate(cwru / "normal" / "97.mat", decimate=4)
rig.save(out / "rig.json")
print(rig, "-> saved as", out / "rig.json")

# %% 5. close the loop on the faulty record, from the machine model
ledger = hf.close_loop(rec.path, fault="outer", machine=rig, seconds=4)
print(ledger)
for e in ledger.effects:
    print("  ", e)

# %% 6. diagnose a directory in parallel (every core, the interpreter released)
t0 = time.perf_counter()
many = hf.diagnose_many(cwru / "12k_drive_end", bearing="6205", baseline=rig)
dt = time.perf_counter() - t0
verdicts = {}
for m in many:
    verdicts[m.verdict] = verdicts.get(m.verdict, 0) + 1
print(f"{len(many)} recordings in {dt:.1f} s: {verdicts}")
