#!/usr/bin/python3
"""Would a dT/dt gain that varies with temperature predict the next run better?

Least squares, on a calibration run, of
    drift = c0 + c1 t + c2 t^2 + c3 t^3 + r (g0 + g1 t + ... + gq t^q),   t = (T - 10) / 50,
r = dT/dt (the centred 300 s least-squares slope `fit` uses), q = 0 (poly(T, dT/dt) as `fit
--model poly --inputs temp,dtemp` fits it, on 1-minute samples), 1 or 2; each applied to the
held-out heating and cooling runs; RMS error against the true drift, mdps. q = 2 is the
first-order expansion of a cubic read at a lagged temperature, f(T - d) ~ f(T) - d f'(T).

Reads the runs bench/drift_admission.py simulated (its D folder):
    D=admission FAMILY=sim2 CAL=two /usr/bin/python3 bench/sim2/gain_vs_temperature.py lag2 1 2 3
FAMILY: sim2 | own; CAL: one | two. Prints per seed and q, then the means over seeds.
"""
import os
import sys

import numpy as np


def load(path):
    return np.genfromtxt(path, delimiter=',', names=True)


def rate(temp, window=300):
    """Centred least-squares slope over `window` samples (truncated at the ends), per sample."""
    h, n = window // 2, len(temp)
    s_t = np.cumsum(np.r_[0.0, temp])
    s_it = np.cumsum(np.r_[0.0, np.arange(n) * temp])
    a = np.maximum(0, np.arange(n) - h)
    b = np.minimum(n - 1, np.arange(n) + h)
    m = b - a + 1
    sxx = m * (m * m - 1) / 12.0
    sxy = (s_it[b + 1] - s_it[a]) - (a + b) / 2.0 * (s_t[b + 1] - s_t[a])
    return np.where(sxx > 0, sxy / np.where(sxx > 0, sxx, 1.0), 0.0)


def basis(temp, r, q):
    t = (temp - 10.0) / 50.0
    cols = [t ** p for p in range(4)] + [100.0 * r * t ** k for k in range(q + 1)]
    return np.vstack(cols).T


def main():
    d, family, cal = os.environ.get('D', 'admission'), os.environ.get('FAMILY', 'sim2'), os.environ.get('CAL', 'two')
    structure, seeds = sys.argv[1], [int(s) for s in sys.argv[2:]]
    errors = {}
    for seed in seeds:
        run = load(f'{d}/{family}.{structure}.{seed}.{cal}.csv')
        y = run['rate_dps']
        for q in (0, 1, 2):
            x = basis(run['temp_c'], rate(run['temp_c']), q)
            beta = np.linalg.lstsq(x[::60], y[::60], rcond=None)[0]
            row = []
            for held in ('heat', 'cool'):
                h = load(f'{d}/{family}.{structure}.{seed}.{held}.csv')
                e = basis(h['temp_c'], rate(h['temp_c']), q) @ beta - h['true_drift_dps']
                row.append(1e3 * float(np.sqrt(np.mean(e * e))))
            errors.setdefault(q, []).append(row)
            print(f'{family} {structure} {cal} seed {seed} q={q}: heating {row[0]:.2f} cooling {row[1]:.2f} mdps')
    for q, rows in errors.items():
        m = np.mean(rows, axis=0)
        print(f'{family} {structure} {cal} q={q}: mean heating {m[0]:.2f} cooling {m[1]:.2f} mdps')


if __name__ == '__main__':
    main()
