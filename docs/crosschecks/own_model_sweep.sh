#!/bin/bash
# The closed loop against its own model, as a user runs it: `hybrid-fdd simulate --params cwru`
# (the bare 5-DOF model, seed 41, 10 s), then `hybrid-fdd close-loop` with the same declared fault
# and speed; 6 fault combinations x 300/900/1797 rpm x 12/48 kHz x noise-free/20 dB SNR.
# `cargo build --release -p hybrid-fdd-cli && bash docs/crosschecks/own_model_sweep.sh` (CSV on stdout)
B=$(realpath "${HYBRID_FDD:-target/release/hybrid-fdd}")
D=$(mktemp -d); cd "$D"
echo "fault,rpm,fs,noise,before,after,effects,seconds"
for fault in none inner outer ball inner+outer inner+outer+ball; do
 for rpm in 300 900 1797; do
  for fs in 12000 48000; do
   for snr in none 20; do
    n=$([ $snr = none ] && echo "" || echo "--snr-db $snr")
    $B simulate --params cwru --fault $fault --rpm $rpm --fs $fs --duration 10 --seed 41 $n --out s.csv >/dev/null 2>&1 || { echo "$fault,$rpm,$fs,$snr,simfail"; continue; }
    line=$($B close-loop --input s.csv --fault $fault --report r.json 2>&1 | tail -1)
    python3 - "$fault" "$rpm" "$fs" "$snr" "$line" <<'PY'
import json,sys,re
r=json.load(open('r.json'))
t=re.search(r'([0-9.]+) s$',sys.argv[5])
print(",".join(sys.argv[1:5]+["%.3f"%r['error_before'],"%.3f"%r['error_after'],"%d"%len(r['effects'])+ (" ["+"; ".join(e['kind'] for e in r['effects'])+"]" if r['effects'] else ""), t.group(1) if t else "?"]))
PY
   done
  done
 done
done
