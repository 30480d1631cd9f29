#!/usr/bin/python3
"""Clearance and overlap of D at its start pose against S, and straight pulls.

    /usr/bin/python3 bench/real/tools/measure.py bench/real/<scene>/scene.yaml [dx dy dz distance]

Loads the scene as scene.md describes it (entries' units and poses, D placed
by start), then reports in scene units: the smallest distance between the
surfaces of D and S, measured from sampled points of each surface (vertices,
two points per edge, centroids) to the other's triangles (an upper bound of
the true distance, exact where the closest points are such samples); how many
of D's samples lie inside S and of S's inside D (generalized winding number >
0.5: overlap at the installed pose); and with a direction, the same count
along a straight pull of D by `distance` in 40 steps (0 everywhere: the pull
is free at these samples).
"""
import os, sys, yaml, numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshtools as mt
MM = {'mm': 1, 'cm': 10, 'm': 1000, 'inch': 25.4}
def entry(e, base, units):
    if isinstance(e, str): e = {'file': e}
    T = mt.load(os.path.join(base, e['file']))
    if 'units' in e: T = T * MM[e['units']] / MM[units]
    p = e.get('pose', {})
    return mt.place(T, np.array(p.get('q', [1, 0, 0, 0]), float), p.get('t', [0, 0, 0]))
def load_scene(path):
    y = yaml.safe_load(open(path)); base = os.path.dirname(path); units = y.get('units', 'mm')
    st = y['static']; st = st if isinstance(st, list) else [st]
    S = np.concatenate([entry(e, base, units) for e in st])
    d = y['dynamic']; d = d if isinstance(d, dict) else {'file': d}
    D = mt.load(os.path.join(base, d['file']))
    if 'units' in d: D = D * MM[d['units']] / MM[units]
    s = y.get('start', {})
    D = mt.place(D, np.array(s.get('q', [1, 0, 0, 0]), float), s.get('t', [0, 0, 0]))
    return S, D, units
def inside(D, S, margin):
    lo, hi = mt.bbox(S); P = mt.near(mt.surface_points(D, 1), S, 0)
    lo2, hi2 = mt.bbox(D); Q = mt.near(mt.surface_points(S, 1), D, 0)
    a = int((mt.winding(P, mt.tris_near(S, *mt.bbox(D), margin)) > 0.5).sum()) if len(P) else 0
    b = int((mt.winding(Q, mt.tris_near(D, *mt.bbox(S), margin)) > 0.5).sum()) if len(Q) else 0
    return a, b
if __name__ == '__main__':
    S, D, units = load_scene(sys.argv[1])
    diag = np.linalg.norm(np.subtract(*mt.bbox(D)))
    g = mt.gap(D, S, 0.05 * diag)
    a, b = inside(D, S, 0.01 * diag)
    print(f'{sys.argv[1]}: units {units}; D {len(D)} triangles, S {len(S)}; min sampled surface distance {g["min_dist"]:.6g} {units}; '
          f'D samples inside S {a}, S samples inside D {b}')
    if len(sys.argv) >= 6:
        v = np.array([float(x) for x in sys.argv[2:5]]); v /= np.linalg.norm(v); dist = float(sys.argv[5])
        worst = 0
        for k in range(1, 41):
            n = inside(D + v * dist * k / 40, S, 0.01 * diag); worst = max(worst, sum(n))
        print(f'  pull {v.tolist()} by {dist} {units}: max samples inside the other over 40 steps: {worst}')
