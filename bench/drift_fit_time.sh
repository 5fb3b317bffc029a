#!/bin/sh
# Wall and CPU time of `gyrocomp fit` on the 14.25 h, 5 Hz paper run (target: auto <= 60 s
# on the 2-core machine). Not a test: timings never decide a test.
# Usage: G=build/gyrocomp D=/tmp/fit-time sh bench/drift_fit_time.sh [models...]   (poly-allan: poly(T, dT/dt) by GLS)
set -e
G=${G:-gyrocomp}
D=${D:-/tmp/gyrocomp-fit-time}
mkdir -p "$D"
[ -f "$D/paper5.csv" ] || $G simulate --profile paper --fs 5 --seed 1 -o "$D/paper5.csv" > /dev/null 2>&1
models=${*:-auto}
for m in $models; do
  case $m in
    poly-allan) args="--model poly --inputs temp,dtemp --noise-model allan" ;;  # GLS (noise_model.h)
    *) args="--model $m" ;;
  esac
  /usr/bin/time -f "$m: %e s wall, %U s user, %S s sys, %M KB peak" \
    $G fit -i "$D/paper5.csv" $args -o "$D/$m.json" --json "$D/$m.fit.json" > /dev/null
done
echo "load: $(cut -d' ' -f1-3 /proc/loadavg) ($(nproc) cores)"
