#!/usr/bin/python3
"""sim2: a second, independent chamber-run simulator for gyrocomp's held-out bench.

Written without reading gyrocomp's model or simulator code (src/drift, src/sim): its
drift structures are deliberately NOT a polynomial in the reported temperature and its
rate, and the temperature the gyro reports is not the temperature that drives the drift.

    chamber set point u(t) --lag 90 s--> board sensor --> temp_c (+0.01 C noise, 1/128 C LSB)
                     \\--structure's own lag(s)--> die temperature Td(t) --> drift(Td, history)
    rate_dps = true_drift(t) + noise(t)       (static unit, no applied rate)

Each run = a hidden pre-history (the unit's life before the log starts: soaks, a quick
pre-cool or pre-heat) + the recorded part. Only the recorded part is written.

Usage as a program:
    sim2.py --structure preisach --profile paper --seed 1 -o run.csv [--no-truth] [--noise-free]
Usage as a module: simulate(structure, profile, seed) -> dict of arrays;
    oracle_basis(structure, run) -> (n, p) matrix of the true form's non-constant columns.
Only numpy is needed.
"""
import argparse
import math
import sys

import numpy as np

FS_HZ = 1.0          # sample rate of the written log
TEMP_SENSOR_LAG_S = 90.0
TEMP_NOISE_C = 0.01
TEMP_LSB_C = 1.0 / 128.0

# ---------------------------------------------------------------------------------------
# Temperature profiles: segments ('set', T) | ('hold', seconds) | ('ramp', T_to, C_per_min)
# ---------------------------------------------------------------------------------------


def _paper_rec():
    seg = [('hold', 3600.0)]
    for t in range(-30, 61, 10):
        seg += [('ramp', float(t), 1.0), ('hold', 3900.0)]
    return seg


def _stairs_rec():
    seg = [('hold', 1800.0)]
    for t in (-20, 0, 20, 40, 60):
        seg += [('ramp', float(t), 1.0), ('hold', 1200.0)]
    for t in (30, 0, -40):
        seg += [('ramp', float(t), 0.5), ('hold', 1200.0)]
    return seg


def _rate_cycles_rec():
    seg = [('hold', 1200.0)]
    for up, down in ((2.0, 1.0), (1.0, 2.0), (2.0, 1.0)):
        seg += [('ramp', 60.0, up), ('hold', 1200.0), ('ramp', -40.0, down), ('hold', 1200.0)]
    return seg


PROFILES = {
    # one direction: soaked cold (after a pre-cool from room), then a slow staircase up
    # -40 -> 60 C in 10 C steps at 1 C/min, each step held 65 min: 13.5 h recorded.
    'paper': dict(pre=[('set', 25.0), ('hold', 4 * 3600.0), ('ramp', -40.0, 1.0), ('hold', 7200.0)],
                  rec=_paper_rec()),
    # 25 -> 60 -> -40 -> 60 C at 0.6 C/min, 30 min holds at the ends: 8.5 h recorded.
    'two-direction': dict(pre=[('set', 25.0), ('hold', 4 * 3600.0)],
                          rec=[('hold', 1800.0), ('ramp', 60.0, 0.6), ('hold', 1800.0),
                               ('ramp', -40.0, 0.6), ('hold', 1800.0), ('ramp', 60.0, 0.6),
                               ('hold', 1800.0)]),
    # held-out heating: quick pre-cool from room (not recorded; die not settled when the log
    # starts), then -40 -> 60 C at 0.7 C/min: 3.1 h recorded.
    'heating': dict(pre=[('set', 25.0), ('hold', 4 * 3600.0), ('ramp', -40.0, 2.0), ('hold', 1200.0)],
                    rec=[('hold', 600.0), ('ramp', 60.0, 0.7), ('hold', 1800.0)]),
    # held-out cooling: quick pre-heat from room, then 60 -> -40 C at 0.7 C/min: 3.1 h.
    'cooling': dict(pre=[('set', 25.0), ('hold', 4 * 3600.0), ('ramp', 60.0, 2.0), ('hold', 1800.0)],
                    rec=[('hold', 600.0), ('ramp', -40.0, 0.7), ('hold', 1800.0)]),
    'stairs': dict(pre=[('set', 25.0), ('hold', 4 * 3600.0), ('ramp', -40.0, 1.0), ('hold', 3600.0)],
                   rec=_stairs_rec()),
    'rate-cycles': dict(pre=[('set', 25.0), ('hold', 4 * 3600.0), ('ramp', -40.0, 1.0), ('hold', 1800.0)],
                        rec=_rate_cycles_rec()),
}


def chamber_profile(name, fs=FS_HZ):
    """Chamber set point u at t = k/fs over pre-history + record; returns (u, n_pre)."""
    p = PROFILES[name]

    def expand(segs, t0):
        pts = []  # (time, temp) breakpoints
        t, temp = 0.0, t0
        for s in segs:
            if s[0] == 'set':
                temp = s[1]
                continue
            if s[0] == 'hold':
                pts.append((t, temp)); t += s[1]; pts.append((t, temp))
            elif s[0] == 'ramp':
                dur = abs(s[1] - temp) / (s[2] / 60.0)
                pts.append((t, temp)); t += dur; temp = s[1]; pts.append((t, temp))
        return pts, temp

    pre_pts, t_end = expand(p['pre'], 25.0)
    rec_pts, _ = expand(p['rec'], t_end)
    pre_dur = pre_pts[-1][0]
    rec_dur = rec_pts[-1][0]
    n_pre = int(round(pre_dur * fs))
    n_rec = int(round(rec_dur * fs)) + 1
    tp = np.arange(n_pre) / fs
    tr = np.arange(n_rec) / fs
    u_pre = np.interp(tp, [a for a, _ in pre_pts], [b for _, b in pre_pts])
    u_rec = np.interp(tr, [a for a, _ in rec_pts], [b for _, b in rec_pts])
    return np.concatenate([u_pre, u_rec]), n_pre


def lag1_fast(x, tau, dt, x0=None):
    """First-order lag dy/dt = (x - y)/tau, exact for x linear over each step (starts at x0 or x[0])."""
    a = math.exp(-dt / tau)
    c1 = 1.0 - (tau / dt) * (1.0 - a)      # weight of x_k
    c0 = (tau / dt) * (1.0 - a) - a        # weight of x_{k-1}
    xs = x.tolist()
    out = [0.0] * len(xs)
    yk = xs[0] if x0 is None else x0
    out[0] = yk
    for k in range(1, len(xs)):
        yk = a * yk + c1 * xs[k] + c0 * xs[k - 1]
        out[k] = yk
    return np.array(out)


def exp_filter(x, tau, dt, y0=0.0):
    """Memory state dm/dt = (x - m)/tau, x held over each step."""
    a = math.exp(-dt / tau)
    xs = x.tolist()
    out = [0.0] * len(xs)
    m = y0
    for k in range(len(xs)):
        m = a * m + (1.0 - a) * xs[k]
        out[k] = m
    return np.array(out)


def preisach(td, centres, halfw, weights, init):
    """Preisach operator: relay hysterons up at c+h, down at c-h; returns sum w*state / sum w."""
    up = centres + halfw
    dn = centres - halfw
    s = init.astype(float).copy()
    out = np.empty(len(td))
    wsum = weights.sum()
    last = None
    val = float(weights @ s) / wsum
    for k, t in enumerate(td.tolist()):
        if last is None or t != last:
            s[t >= up] = 1.0
            s[t <= dn] = -1.0
            val = float(weights @ s) / wsum
            last = t
        out[k] = val
    return out


# ---------------------------------------------------------------------------------------
# Drift structures. Each: latent(u, dt) -> dict of latent states; basis(lat) -> (names,
# columns); coef: true amplitudes of the columns; offset. drift = offset + columns @ coef.
# ---------------------------------------------------------------------------------------

SOFT_SIGN_C_PER_S = 0.2 / 60.0   # tanh(dTd/dt / s0): "heating" once the die moves > 0.2 C/min

_PREISACH_RNG = np.random.default_rng(20261128)
_NH = 400
_PRE_CENTRES = _PREISACH_RNG.uniform(-45.0, 65.0, _NH)
_PRE_HALFW = np.abs(_PREISACH_RNG.normal(0.0, 6.0, _NH)) + 0.5
_PRE_WEIGHTS = _PREISACH_RNG.uniform(0.5, 1.5, _NH)
_PRE_COIN = _PREISACH_RNG.choice([-1.0, 1.0], _NH)


def _lat_lag2(u, dt):
    a = lag1_fast(u, 600.0, dt)
    td = lag1_fast(a, 120.0, dt)
    return dict(td=td)


def _basis_lag2(L):
    td = L['td']
    return ['tanh((Td-10)/15)', 'exp(Td/30)'], np.column_stack([np.tanh((td - 10.0) / 15.0), np.exp(td / 30.0)])


def _lat_die(tau):
    def f(u, dt):
        td = lag1_fast(u, tau, dt)
        # exact derivative of the lag state: (u - Td)/tau
        return dict(td=td, dtd=(u - td) / tau)
    return f


def _lat_preisach(u, dt):
    L = _lat_die(600.0)(u, dt)
    t0 = L['td'][0]
    init = np.where(_PRE_CENTRES + _PRE_HALFW <= t0, 1.0,
                    np.where(_PRE_CENTRES - _PRE_HALFW >= t0, -1.0, _PRE_COIN))
    L['p'] = preisach(L['td'], _PRE_CENTRES, _PRE_HALFW, _PRE_WEIGHTS, init)
    return L


def _basis_preisach(L):
    td = L['td']
    return (['tanh(Td/25)', 'gauss((Td-35)/18)', 'Preisach(Td)'],
            np.column_stack([np.tanh(td / 25.0), np.exp(-((td - 35.0) / 18.0) ** 2), L['p']]))


def _lat_memory(tau_die, tau_mem):
    def f(u, dt):
        L = _lat_die(tau_die)(u, dt)
        L['m'] = exp_filter(np.tanh(L['dtd'] / SOFT_SIGN_C_PER_S), tau_mem, dt, 0.0)
        return L
    return f


def _basis_memory(L):
    td = L['td']
    return (['atan((Td-15)/20)', 'exp((Td-60)/20)', 'mem1800'],
            np.column_stack([np.arctan((td - 15.0) / 20.0), np.exp((td - 60.0) / 20.0), L['m']]))


def _softplus(x):
    return np.logaddexp(0.0, x)


def _basis_rate_temp(L):
    td, r = L['td'], L['dtd']
    return (['softplus((Td-5)/12)', 'dTd/dt', 'tanh((Td-20)/20)*dTd/dt', 'mem3600'],
            np.column_stack([_softplus((td - 5.0) / 12.0), r, np.tanh((td - 20.0) / 20.0) * r, L['m']]))


def _basis_smooth(L):
    td = L['td']
    return (['sigmoid((Td-20)/6)', 'sin(2pi Td/35+0.7)'],
            np.column_stack([1.0 / (1.0 + np.exp(-(td - 20.0) / 6.0)),
                             np.sin(2.0 * np.pi * td / 35.0 + 0.7)]))


STRUCTURES = {
    # die = second-order lag of the chamber (600 s, 120 s); drift = a tanh + b exp (deg/s)
    'lag2': dict(latent=_lat_lag2, basis=_basis_lag2, coef=np.array([0.08, 0.010]), offset=-0.02,
                 doc='Td = L120(L600(u)); drift = -0.02 + 0.08 tanh((Td-10)/15) + 0.010 exp(Td/30)'),
    # unit-A-like die lag (600 s) + Preisach hysteresis (400 relays, random thresholds)
    'preisach': dict(latent=_lat_preisach, basis=_basis_preisach, coef=np.array([0.06, 0.025, 0.015]),
                     offset=0.01,
                     doc='Td = L600(u); drift = 0.01 + 0.06 tanh(Td/25) + 0.025 exp(-((Td-35)/18)^2) '
                         '+ 0.015 P[Td] (Preisach, relays c +- h, c ~ U(-45,65), h ~ |N(0,6)|+0.5)'),
    # unit A of the issue: 600 s die lag and a heating/cooling memory of 1800 s
    'memory': dict(latent=_lat_memory(600.0, 1800.0), basis=_basis_memory,
                   coef=np.array([0.07, 0.015, 0.012]), offset=0.0,
                   doc='Td = L600(u); m: dm/dt = (tanh(dTd/dt / 0.2 C/min) - m)/1800 s; '
                       'drift = 0.07 atan((Td-15)/20) + 0.015 exp((Td-60)/20) + 0.012 m'),
    # unit B of the issue: 300 s lag, rate effect whose gain depends on T, 3600 s memory
    'rate-temp': dict(latent=_lat_memory(300.0, 3600.0), basis=_basis_rate_temp,
                      coef=np.array([0.03, 1.2, 0.6, 0.008]), offset=-0.03,
                      doc='Td = L300(u); m: dm/dt = (tanh(dTd/dt / 0.2 C/min) - m)/3600 s; '
                          'drift = -0.03 + 0.03 softplus((Td-5)/12) + 1.2 (1 + 0.5 tanh((Td-20)/20)) dTd/dt '
                          '+ 0.008 m'),
    # no memory, single 400 s lag; a sigmoid plus a sinusoidal ripple in T
    'smooth-nonpoly': dict(latent=_lat_die(400.0), basis=_basis_smooth, coef=np.array([0.10, 0.012]),
                           offset=-0.05,
                           doc='Td = L400(u); drift = -0.05 + 0.10 / (1 + exp(-(Td-20)/6)) '
                               '+ 0.012 sin(2 pi Td / 35 + 0.7)'),
}

# ---------------------------------------------------------------------------------------
# Noise
# ---------------------------------------------------------------------------------------

DEFAULT_NOISE = dict(
    arw_deg_per_sqrt_h=0.3,         # white
    bias_instability_deg_per_h=15.0,  # flicker: sum of AR(1), 3 per decade, 3 s .. 3e5 s
    rrw_deg_per_h_per_sqrt_h=2.0,   # random walk
    ar1_sigma_deg_per_h=6.0,        # AR(1) ...
    ar1_tau_s=240.0,                # ... with a 4-minute correlation time
)


def _gm_avar(q2, T, tau):
    """Allan variance of a Gauss-Markov process of variance q2 and correlation time T."""
    x = tau / T
    return (2.0 * q2 * T / tau) * (1.0 - (1.0 / (2.0 * x)) * (3.0 - 4.0 * np.exp(-x) + np.exp(-2.0 * x)))


FLICKER_T = np.logspace(np.log10(3.0), np.log10(3e5), 16)  # 3 per decade


def _flicker_q2(b_deg_h):
    floor = 0.664 * b_deg_h / 3600.0  # deg/s
    tau_mid = math.sqrt(FLICKER_T[0] * FLICKER_T[-1])
    unit = sum(_gm_avar(1.0, T, tau_mid) for T in FLICKER_T)
    return floor ** 2 / unit


def ar1(rng, n, tau, sigma, dt):
    phi = math.exp(-dt / tau)
    e = rng.standard_normal(n) * sigma * math.sqrt(1.0 - phi * phi)
    e[0] = rng.standard_normal() * sigma
    xs = e.tolist()
    out = [0.0] * n
    x = 0.0
    for k in range(n):
        x = phi * x + xs[k] if k else xs[0]
        out[k] = x
    return np.array(out)


def noise(rng, n, dt, p=DEFAULT_NOISE):
    w = rng.standard_normal(n) * (p['arw_deg_per_sqrt_h'] / 60.0) / math.sqrt(dt)
    q = math.sqrt(_flicker_q2(p['bias_instability_deg_per_h']))
    fl = np.zeros(n)
    for T in FLICKER_T:
        fl += ar1(rng, n, T, q, dt)
    rw = np.cumsum(rng.standard_normal(n)) * (p['rrw_deg_per_h_per_sqrt_h'] / 216000.0) * math.sqrt(dt)
    a1 = ar1(rng, n, p['ar1_tau_s'], p['ar1_sigma_deg_per_h'] / 3600.0, dt)
    return w + fl + rw + a1


# ---------------------------------------------------------------------------------------
# A run
# ---------------------------------------------------------------------------------------

STRUCT_INDEX = {k: i for i, k in enumerate(STRUCTURES)}
PROFILE_INDEX = {k: i for i, k in enumerate(PROFILES)}


def simulate(structure, profile, seed, fs=FS_HZ, noise_params=None):
    st = STRUCTURES[structure]
    dt = 1.0 / fs
    u, n_pre = chamber_profile(profile, fs)
    lat = st['latent'](u, dt)
    board = lag1_fast(u, TEMP_SENSOR_LAG_S, dt)
    sl = slice(n_pre, None)
    lat = {k: v[sl] for k, v in lat.items()}
    _, cols = st['basis'](lat)
    drift = st['offset'] + cols @ st['coef']
    n = len(drift)
    rng = np.random.default_rng([int(seed), STRUCT_INDEX[structure], PROFILE_INDEX[profile], 7])
    nz = noise(rng, n, dt, noise_params or DEFAULT_NOISE)
    temp = board[sl] + rng.standard_normal(n) * TEMP_NOISE_C
    temp = np.round(temp / TEMP_LSB_C) * TEMP_LSB_C
    return dict(time_s=np.arange(n) * dt, rate_dps=drift + nz, temp_c=temp, true_drift_dps=drift,
                chamber_temp_c=u[sl], die_temp_c=lat['td'], latent=lat)


def oracle_basis(structure, run):
    return STRUCTURES[structure]['basis'](run['latent'])[1]


def write_csv(path, run, truth=True):
    cols = ['time_s', 'rate_dps', 'temp_c'] + (['true_drift_dps', 'chamber_temp_c', 'die_temp_c'] if truth else [])
    fmts = ['%.1f', '%.9f', '%.6f', '%.9f', '%.4f', '%.4f'][:len(cols)]
    data = np.column_stack([run[c] for c in cols])
    np.savetxt(path, data, fmt=fmts, delimiter=',', header=','.join(cols), comments='')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--structure', choices=list(STRUCTURES), required=True)
    ap.add_argument('--profile', choices=list(PROFILES), default='paper')
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--fs', type=float, default=FS_HZ)
    ap.add_argument('-o', '--output', required=True)
    ap.add_argument('--no-truth', action='store_true', help='leave out true_drift_dps, chamber_temp_c, die_temp_c')
    ap.add_argument('--noise-free', action='store_true',
                    help='rate_dps = the true drift (no gyro noise; the thermometer keeps its noise and LSB): what '
                         'the run shows of the drift\'s form alone')
    a = ap.parse_args()
    run = simulate(a.structure, a.profile, a.seed, a.fs)
    if a.noise_free:
        run['rate_dps'] = run['true_drift_dps']
    write_csv(a.output, run, truth=not a.no_truth)
    d = run['true_drift_dps']
    print(f'{a.output}: {len(d)} samples, {len(d) / a.fs / 3600:.2f} h, true drift {d.min():+.4f} .. {d.max():+.4f} dps',
          file=sys.stderr)


if __name__ == '__main__':
    main()
