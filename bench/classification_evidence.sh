#!/bin/bash
# Reproduces the tables of docs/explanation/classification.md: VMD + sample entropy + class of every mode
# (gyrocomp decompose, default rule) on simulated chamber records, where the true drift is known
# (its squared correlation with each mode is printed), and on the ADIS16405 run 1 record.
#   bash bench/classification_evidence.sh BUILD_DIR [OUT_DIR]
# Takes a few minutes on 2 cores (the 100 Hz paper run is 5.1 million samples; VMD needs ~2 GB).
set -euo pipefail
BUILD=${1:?usage: classification_evidence.sh BUILD_DIR [OUT_DIR]}
OUT=${2:-$(mktemp -d)}
G=$BUILD/gyrocomp
REAL=$(dirname "$0")/../../shared/realdata
mkdir -p "$OUT"

# Squared correlation of each mode with the simulator's true drift (python3 standard library).
corr() {
  python3 - "$1" "$2" <<'PY'
import csv, gzip, sys, math
sim, modes = sys.argv[1], sys.argv[2]
op = gzip.open if sim.endswith('.gz') else open
with op(sim, 'rt') as f:
    r = csv.reader(f); h = next(r); j = h.index('true_drift_dps')
    d = [float(row[j]) for row in r]
with open(modes) as f:
    r = csv.reader(f); names = next(r); cols = [[] for _ in names]
    for row in r:
        for k, v in enumerate(row): cols[k].append(float(v))
def c2(a, b):
    n = len(a); ma = sum(a) / n; mb = sum(b) / n
    ab = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    aa = sum((x - ma) ** 2 for x in a); bb = sum((y - mb) ** 2 for y in b)
    return ab * ab / (aa * bb) if aa > 0 and bb > 0 else 0.0
print('  drift corr^2: ' + ' '.join('%s=%.3f' % (nm, c2(c, d)) for nm, c in zip(names, cols)))
PY
}

run_sim() {  # name, simulate options...
  local name=$1; shift
  "$G" simulate "$@" -o "$OUT/$name.csv.gz" > /dev/null
  echo "== $name: gyrocomp simulate $* ; gyrocomp decompose -i $name.csv.gz --modes 6"
  "$G" decompose -i "$OUT/$name.csv.gz" --modes 6 -o "$OUT/$name.modes.csv" --json "$OUT/$name.json"
  corr "$OUT/$name.csv.gz" "$OUT/$name.modes.csv"
}

run_sim paper_fs10_seed1 --profile paper --fs 10 --seed 1
run_sim paper_fs10_seed2 --profile paper --fs 10 --seed 2
run_sim cycle_fs10_seed1 --profile cycle --fs 10 --seed 1
run_sim paper_fs10_sine --profile paper --fs 10 --seed 1 --sine-amplitude 0.05 --sine-frequency 0.5
run_sim paper_fs100_seed1 --profile paper --fs 100 --seed 1

if [ -f "$REAL/adis16405_run1.csv.gz" ]; then
  echo "== adis16405_run1: gyrocomp decompose --time-col t_s --rate-col gx_dps,gy_dps,gz_dps --modes 6"
  "$G" decompose -i "$REAL/adis16405_run1.csv.gz" --time-col t_s --rate-col gx_dps,gy_dps,gz_dps --modes 6 \
    --json "$OUT/adis16405_run1.json"
else
  echo "(no ../shared/realdata: ADIS record skipped)"
fi
echo "outputs in $OUT"
