#!/usr/bin/python3
"""Held-out bench on sim2's runs: gyrocomp fit/apply against the true drift and an oracle.

For each structure x seed x calibration profile (paper = one direction, two-direction):
  (a) gyrocomp fit --model auto                        on the calibration run
  (b) gyrocomp fit --model poly --inputs temp,dtemp    on the same run
  (c) gyrocomp fit --model poly --inputs temp,dtemp    on the paper run (the reference)
  (d) oracle: least squares of the TRUE form (its nonlinear parameters and latent states known,
      linear amplitudes + offset refitted) on the calibration run
each applied to a held-out heating run and a held-out cooling run (own noise seeds, own
pre-histories). Error = predicted drift - true drift over the whole recorded held-out run, RMS
in mdps. Band coverage: share of held-out samples whose true drift lies in auto's
predicted_drift_lo_dps .. predicted_drift_hi_dps (the 90% band apply writes).

Usage:
  bench/sim2/heldout.py [--gyrocomp PATH] [--seeds 6] [--structures a,b] [--quick] [--jobs 2]
                        [--out bench/sim2/out] [--keep] [--cals paper,two-direction,stairs,rate-cycles]
GYROCOMP env var (default build/gyrocomp) names the binary when --gyrocomp is not given.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import time
from multiprocessing import Pool

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import sim2  # noqa: E402

CALS = ['paper', 'two-direction']
HELDOUT = ['heating', 'cooling']


def run(cmd, log):
    t = time.time()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(log, 'a') as f:
        f.write('$ ' + ' '.join(cmd) + '\n' + p.stdout + f'[exit {p.returncode}, {time.time() - t:.1f} s]\n')
    if p.returncode != 0:
        raise RuntimeError(f'{" ".join(cmd)} failed ({p.returncode}): {p.stdout[-2000:]}')
    return time.time() - t


def read_csv(path, cols):
    with open(path) as f:
        header = f.readline().strip().split(',')
    idx = [header.index(c) for c in cols]
    data = np.loadtxt(path, delimiter=',', skiprows=1, usecols=idx, ndmin=2)
    return {c: data[:, i] for i, c in enumerate(cols)}


def rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


def job(args):
    structure, seed, gyro, outdir, keep, cals = args
    global CALS
    CALS = cals
    wd = os.path.join(outdir, 'work', f'{structure}_s{seed}')
    os.makedirs(wd, exist_ok=True)
    log = os.path.join(wd, 'log.txt')
    open(log, 'w').close()
    t0 = time.time()
    runs = {}
    for prof in CALS + HELDOUT:
        r = sim2.simulate(structure, prof, seed)
        # the calibration runs carry no truth column (nothing for a fit to pick up);
        # the held-out runs carry true_drift_dps (apply scores it too: cross-check)
        sim2.write_csv(os.path.join(wd, f'{prof}.csv'), r, truth=prof in HELDOUT)
        runs[prof] = r
    rec = dict(structure=structure, seed=seed, fits={}, results={}, cli_s=0.0)
    models = {}
    for cal in CALS:
        for kind, extra in (('auto', ['--model', 'auto']), ('poly', ['--model', 'poly', '--inputs', 'temp,dtemp'])):
            m = os.path.join(wd, f'{kind}_{cal}.json')
            fj = os.path.join(wd, f'{kind}_{cal}.fit.json')
            rec['cli_s'] += run([gyro, 'fit', '-i', os.path.join(wd, f'{cal}.csv')] + extra +
                                ['--threads', '1', '-o', m, '--json', fj], log)
            with open(fj) as f:
                fd = json.load(f)
            rec['fits'][f'{kind}_{cal}'] = dict(model=fd.get('model'), inputs=fd.get('inputs'),
                                                cv_rmse_dps=fd.get('cv_rmse_dps'),
                                                excluded=[e.get('term') for e in fd.get('excluded_terms', []) or []])
            models[(kind, cal)] = m
    # oracle coefficients on each calibration run
    ocoef = {}
    for cal in CALS:
        X = np.column_stack([np.ones(len(runs[cal]['rate_dps'])), sim2.oracle_basis(structure, runs[cal])])
        ocoef[cal] = np.linalg.lstsq(X, runs[cal]['rate_dps'], rcond=None)[0]
    for h in HELDOUT:
        truth = runs[h]['true_drift_dps']
        res = {}
        for (kind, cal), m in models.items():
            oc = os.path.join(wd, f'comp_{kind}_{cal}_{h}.csv')
            aj = os.path.join(wd, f'apply_{kind}_{cal}_{h}.json')
            rec['cli_s'] += run([gyro, 'apply', '-m', m, '-i', os.path.join(wd, f'{h}.csv'), '-o', oc, '--json', aj], log)
            with open(oc) as f:
                header = f.readline().strip().split(',')
            cols = ['true_drift_dps', 'predicted_drift_dps']
            has_band = 'predicted_drift_lo_dps' in header
            if has_band:
                cols += ['predicted_drift_lo_dps', 'predicted_drift_hi_dps']
            d = read_csv(oc, cols)
            assert np.allclose(d['true_drift_dps'], truth, atol=1e-8)
            e = d['predicted_drift_dps'] - truth
            r = dict(rms_mdps=1e3 * rms(e), mean_mdps=1e3 * float(np.mean(e)))
            if has_band:
                inside = (truth >= d['predicted_drift_lo_dps']) & (truth <= d['predicted_drift_hi_dps'])
                r['band_coverage'] = float(np.mean(inside))
                r['band_half_width_rms_mdps'] = 1e3 * rms(0.5 * (d['predicted_drift_hi_dps'] - d['predicted_drift_lo_dps']))
            with open(aj) as f:
                ad = json.load(f)
            r['cli_rmse_mdps'] = 1e3 * ad['rmse_vs_true_drift_dps'] if ad.get('rmse_vs_true_drift_dps') is not None else None
            r['cli_band_coverage'] = ad.get('band_coverage_of_true_drift_dps')
            r['band_level'] = ad.get('band_level')
            res[f'{kind}_{cal}'] = r
            if not keep:
                os.remove(oc)
        for cal in CALS:
            X = np.column_stack([np.ones(len(truth)), sim2.oracle_basis(structure, runs[h])])
            e = X @ ocoef[cal] - truth
            res[f'oracle_{cal}'] = dict(rms_mdps=1e3 * rms(e), mean_mdps=1e3 * float(np.mean(e)))
        rec['results'][h] = res
    rec['oracle_coef'] = {c: v.tolist() for c, v in ocoef.items()}
    rec['wall_s'] = time.time() - t0
    if not keep:
        for prof in CALS + HELDOUT:
            os.remove(os.path.join(wd, f'{prof}.csv'))
    with open(os.path.join(wd, 'record.json'), 'w') as f:
        json.dump(rec, f, indent=1)
    print(f'  {structure} seed {seed}: {rec["wall_s"]:.0f} s', file=sys.stderr, flush=True)
    return rec


def record_from_workdir(structure, seed, outdir, cals):
    """A finished job's record: its record.json, else rebuilt from the fit/apply JSONs it left
    (RMS and coverage as apply computed them against true_drift_dps; the oracle recomputed).
    None when the job has not finished."""
    wd = os.path.join(outdir, 'work', f'{structure}_s{seed}')
    p = os.path.join(wd, 'record.json')
    if os.path.exists(p):
        with open(p) as f:
            rec = json.load(f)
        if all(f'auto_{c}' in rec['fits'] for c in cals):
            return rec
        return None
    need = [os.path.join(wd, f'apply_{k}_{c}_{h}.json') for k in ('auto', 'poly') for c in cals for h in HELDOUT]
    if not all(os.path.exists(x) for x in need):
        return None
    rec = dict(structure=structure, seed=seed, fits={}, results={}, rebuilt_from_cli_json=True)
    for k in ('auto', 'poly'):
        for c in cals:
            with open(os.path.join(wd, f'{k}_{c}.fit.json')) as f:
                fd = json.load(f)
            rec['fits'][f'{k}_{c}'] = dict(model=fd.get('model'), inputs=fd.get('inputs'),
                                           cv_rmse_dps=fd.get('cv_rmse_dps'),
                                           excluded=[e.get('term') for e in fd.get('excluded_terms', []) or []])
    runs = {p: sim2.simulate(structure, p, seed) for p in cals + HELDOUT}
    ocoef = {}
    for c in cals:
        X = np.column_stack([np.ones(len(runs[c]['rate_dps'])), sim2.oracle_basis(structure, runs[c])])
        ocoef[c] = np.linalg.lstsq(X, runs[c]['rate_dps'], rcond=None)[0]
    for h in HELDOUT:
        truth = runs[h]['true_drift_dps']
        res = {}
        for k in ('auto', 'poly'):
            for c in cals:
                with open(os.path.join(wd, f'apply_{k}_{c}_{h}.json')) as f:
                    ad = json.load(f)
                r = dict(rms_mdps=1e3 * ad['rmse_vs_true_drift_dps'], cli_rmse_mdps=1e3 * ad['rmse_vs_true_drift_dps'],
                         cli_band_coverage=ad.get('band_coverage_of_true_drift_dps'), band_level=ad.get('band_level'))
                if ad.get('band_coverage_of_true_drift_dps') is not None:
                    r['band_coverage'] = ad['band_coverage_of_true_drift_dps']
                res[f'{k}_{c}'] = r
        for c in cals:
            X = np.column_stack([np.ones(len(truth)), sim2.oracle_basis(structure, runs[h])])
            e = X @ ocoef[c] - truth
            res[f'oracle_{c}'] = dict(rms_mdps=1e3 * rms(e), mean_mdps=1e3 * float(np.mean(e)))
        rec['results'][h] = res
    rec['oracle_coef'] = {c: v.tolist() for c, v in ocoef.items()}
    return rec


def fmt_stat(v, digits=1):
    v = np.asarray(v, float)
    return f'{np.median(v):.{digits}f} [{v.min():.{digits}f}-{v.max():.{digits}f}]'


def summarise(records, structures):
    rows, table = [], []
    hdr = ('| structure | cal | held-out | auto | poly(T,dT) same run | ref poly(T,dT) paper | oracle | '
           'auto/poly-same | auto/ref | oracle/ref | auto 90% band coverage | auto chose |')
    table.append(hdr)
    table.append('|' + '---|' * 12)
    for s in structures:
        recs = [r for r in records if r['structure'] == s]
        if not recs:
            continue
        for cal in CALS:
            chose = {}
            for r in recs:
                f = r['fits'][f'auto_{cal}']
                k = f'{f["model"]}({f["inputs"]})'
                chose[k] = chose.get(k, 0) + 1
            chose_s = ', '.join(f'{k} x{v}' for k, v in sorted(chose.items(), key=lambda kv: -kv[1]))
            for h in HELDOUT:
                g = lambda key: np.array([r['results'][h][key]['rms_mdps'] for r in recs])  # noqa: E731
                a, p, ref, o = g(f'auto_{cal}'), g(f'poly_{cal}'), g('poly_paper'), g(f'oracle_{cal}')
                cov = [r['results'][h][f'auto_{cal}'].get('band_coverage') for r in recs]
                cov = [c for c in cov if c is not None]
                row = dict(structure=s, cal=cal, heldout=h, n_seeds=len(recs),
                           auto_mdps=a.tolist(), poly_same_mdps=p.tolist(), ref_mdps=ref.tolist(),
                           oracle_mdps=o.tolist(), auto_over_poly_same=(a / p).tolist(),
                           auto_over_ref=(a / ref).tolist(), oracle_over_ref=(o / ref).tolist(),
                           auto_band_coverage=cov, auto_chose=chose)
                rows.append(row)
                table.append(f'| {s} | {cal} | {h} | {fmt_stat(a)} | {fmt_stat(p)} | {fmt_stat(ref)} | {fmt_stat(o)} | '
                             f'{fmt_stat(a / p, 2)} | {fmt_stat(a / ref, 2)} | {fmt_stat(o / ref, 2)} | '
                             f'{fmt_stat(cov, 2) if cov else "n/a"} | {chose_s} |')
    return rows, '\n'.join(table)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--gyrocomp', default=os.environ.get('GYROCOMP', 'build/gyrocomp'))
    ap.add_argument('--seeds', type=int, default=6)
    ap.add_argument('--first-seed', type=int, default=1)
    ap.add_argument('--structures', default=','.join(sim2.STRUCTURES))
    ap.add_argument('--quick', action='store_true', help='2 seeds (unless --seeds is given explicitly)')
    ap.add_argument('--jobs', type=int, default=2, help='parallel processes (at most 2 on the shared machine)')
    ap.add_argument('--out', default=os.path.join(os.path.dirname(os.path.abspath(__file__)), 'out'))
    ap.add_argument('--keep', action='store_true', help='keep the simulated and compensated CSVs')
    ap.add_argument('--summarise-only', action='store_true',
                    help='no new jobs: summarise the finished jobs found in --out (a partial run too)')
    ap.add_argument('--resume', action='store_true', help='reuse the finished jobs found in --out')
    ap.add_argument('--cals', default='paper,two-direction',
                    help='calibration profiles (sim2.PROFILES; must include paper, the reference)')
    a = ap.parse_args()
    if a.quick and '--seeds' not in sys.argv:
        a.seeds = 2
    structures = a.structures.split(',')
    global CALS
    CALS = a.cals.split(',')
    if 'paper' not in CALS or any(c not in sim2.PROFILES or c in HELDOUT for c in CALS):
        sys.exit(f'heldout.py: --cals {a.cals}: calibration profiles from {", ".join(sim2.PROFILES)}, '
                 f'not {", ".join(HELDOUT)}, including paper')
    for s in structures:
        if s not in sim2.STRUCTURES:
            sys.exit(f'heldout.py: unknown structure {s!r} (have {", ".join(sim2.STRUCTURES)})')
    seeds = list(range(a.first_seed, a.first_seed + a.seeds))
    if a.summarise_only or a.resume:
        done = {}
        for st in structures:
            for seed in seeds:
                r = record_from_workdir(st, seed, a.out, CALS)
                if r is not None:
                    done[(st, seed)] = r
        print(f'heldout.py: {len(done)} finished jobs found in {a.out}', file=sys.stderr)
    else:
        done = {}
    if a.summarise_only:
        records = [done[k] for k in sorted(done, key=lambda k: (structures.index(k[0]), k[1]))]
        rows, table = summarise(records, structures)
        nseed = {st: sum(1 for k in done if k[0] == st) for st in structures}
        head = (f'PARTIAL/summary-only: finished seeds per structure {nseed}. RMS error of the predicted drift vs '
                f'the true drift on the held-out run, mdps: median [min-max] over seeds; ratios per seed, then '
                f'median [min-max]. Band: auto\'s 90% band, share of held-out samples whose true drift lies inside.\n\n')
        with open(os.path.join(a.out, 'heldout_summary_only.json'), 'w') as f:
            json.dump(dict(summary=rows, records=records, structures=structures, seeds=seeds), f, indent=1)
        with open(os.path.join(a.out, 'heldout_summary_only.md'), 'w') as f:
            f.write(head + table + '\n')
        print(head + table)
        return
    if not os.access(a.gyrocomp, os.X_OK):
        sys.exit(f'heldout.py: no gyrocomp binary at {a.gyrocomp} (set --gyrocomp or GYROCOMP)')
    gyro = os.path.abspath(a.gyrocomp)
    os.makedirs(a.out, exist_ok=True)
    jobs = [(s, seed, gyro, a.out, a.keep, CALS) for s in structures for seed in seeds if (s, seed) not in done]
    t0 = time.time()
    print(f'heldout.py: {len(jobs)} jobs ({len(structures)} structures x {a.seeds} seeds), {a.jobs} processes, {gyro}',
          file=sys.stderr)
    n = max(1, min(2, a.jobs))
    if n == 1:
        records = [job(j) for j in jobs]
    else:
        with Pool(n) as pool:
            records = pool.map(job, jobs, chunksize=1)
    records = sorted(records + list(done.values()), key=lambda r: (structures.index(r['structure']), r['seed']))
    wall = time.time() - t0
    rows, table = summarise(records, structures)
    out = dict(gyrocomp=gyro, seeds=list(range(a.first_seed, a.first_seed + a.seeds)), structures=structures,
               structure_docs={s: sim2.STRUCTURES[s]['doc'] for s in structures}, noise=sim2.DEFAULT_NOISE,
               wall_s=wall, summary=rows, records=records)
    with open(os.path.join(a.out, 'heldout.json'), 'w') as f:
        json.dump(out, f, indent=1)
    head = (f'RMS error of the predicted drift vs the true drift on the held-out run, mdps: median [min-max] over '
            f'{a.seeds} seeds; ratios per seed, then median [min-max]. Band: auto\'s 90% prediction band '
            f'(apply\'s predicted_drift_lo/hi_dps), share of held-out samples whose true drift lies inside. '
            f'Wall {wall:.0f} s.\n\n')
    with open(os.path.join(a.out, 'heldout.md'), 'w') as f:
        f.write(head + table + '\n')
    print(head + table)


if __name__ == '__main__':
    main()
