#!/bin/sh
# Decomposition of the held-out drift error: the runs of bench/drift_heldout.sh with one
# simulator term switched off at a time, fitted with poly(T, dT/dt) (and MODELS, e.g. "poly hybrid";
# hybrid-keep = the hybrid with its kernel always kept, --keep-kernel).
# Prints one row per (structure, variant, seed, model): heating and cooling-2 RMSE against the
# true drift, mdps. "none" = all noise off (white, flicker, RRW, temperature reading noise).
# Usage: G=build/gyrocomp D=decomp FS=1 MODELS="poly" STRUCTS="A B C D" sh bench/drift_decompose.sh
set -e
G=${G:-gyrocomp}
D=${D:-decomp}
FS=${FS:-1}
GEN=${GEN:-4}
MODELS=${MODELS:-poly}
STRUCTS=${STRUCTS:-A B C D}
VARIANTS=${VARIANTS:-full no-white no-flicker no-rrw no-noise no-hyst no-rate no-noise-hyst}
SEEDS=${SEEDS:-1 2 3}
mkdir -p "$D"
structure() {  # keep in step with bench/drift_heldout.sh
  case $1 in
    A) echo "" ;;
    B) echo "--hysteresis-width 10 --hysteresis-coeff 4e-3 --dtemp-coeff 0.5" ;;
    C) echo "--thermal-lag 1500 --dtemp-coeff 4" ;;
    D) echo "--hysteresis-coeff 0 --thermal-lag 300 --dtemp-coeff 2.5 --drift-poly 0.01,-1e-3,3e-5,1e-7" ;;
  esac
}
variant() {
  case $1 in
    full) echo "" ;;
    no-white) echo "--arw 0" ;;
    no-flicker) echo "--bias-instability 0" ;;
    no-rrw) echo "--rrw 0" ;;
    no-noise) echo "--arw 0 --bias-instability 0 --rrw 0 --temp-noise 0" ;;
    no-hyst) echo "--hysteresis-coeff 0" ;;
    no-rate) echo "--dtemp-coeff 0" ;;
    no-noise-hyst) echo "--arw 0 --bias-instability 0 --rrw 0 --temp-noise 0 --hysteresis-coeff 0" ;;
  esac
}
combine() {  # structure flags, then the variant's; a variant option replaces the structure's
  set -- $1
  out=""
  while [ $# -ge 2 ]; do
    case " $VFLAGS " in *" $1 "*) ;; *) out="$out $1 $2" ;; esac
    shift 2
  done
  echo "$out $VFLAGS"
}
echo "| structure | variant | seed | model | chosen | heating RMSE (mdps) | cooling-2 RMSE (mdps) |"
echo "|---|---|---|---|---|---|---|"
for S in $STRUCTS; do
  for V in $VARIANTS; do
    VFLAGS=$(variant $V)
    F=$(combine "$(structure $S)")
    for seed in $SEEDS; do
      p="$D/$S.$V.$seed"
      $G simulate --profile paper --fs $FS --seed $seed $F -o $p.cool.csv > /dev/null 2>&1
      $G simulate --profile ramp --room-temp -40 --ramp-end 60 --fs $FS --seed $((seed + 10)) $F -o $p.heat.csv > /dev/null 2>&1
      $G simulate --profile paper --fs $FS --seed $((seed + 20)) $F -o $p.cool2.csv > /dev/null 2>&1
      for M in $MODELS; do
        case $M in
          auto) args="--model auto" ;;
          hybrid|cs-svr) args="--model $M --inputs temp,dtemp --generations $GEN" ;;
          hybrid-keep) args="--model hybrid --inputs temp,dtemp --generations $GEN --keep-kernel" ;;  # Eq. H-1 off
          *) args="--model $M --inputs temp,dtemp" ;;
        esac
        $G fit -i $p.cool.csv $args -o $p.$M.json --json $p.$M.fit.json > /dev/null 2>&1
        $G apply -m $p.$M.json -i $p.heat.csv -o $p.$M.h.csv --json $p.$M.heat.json > /dev/null 2>&1
        $G apply -m $p.$M.json -i $p.cool2.csv -o $p.$M.c.csv --json $p.$M.cool2.json > /dev/null 2>&1
        rm -f $p.$M.h.csv $p.$M.c.csv
        /usr/bin/python3 - "$p" "$M" "$S" "$V" "$seed" <<'PY'
import json, sys
p, m, s, v, seed = sys.argv[1:]
f = json.load(open(f"{p}.{m}.fit.json")); h = json.load(open(f"{p}.{m}.heat.json")); c = json.load(open(f"{p}.{m}.cool2.json"))
print(f"| {s} | {v} | {seed} | {m} | {f['model']}({f['inputs']}) | {1000*h['rmse_vs_true_drift_dps']:.2f} | {1000*c['rmse_vs_true_drift_dps']:.2f} |")
PY
      done
      rm -f $p.cool.csv $p.heat.csv $p.cool2.csv
    done
  done
done
