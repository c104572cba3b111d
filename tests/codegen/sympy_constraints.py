#!/usr/bin/env python3
"""Independent check of constrained models with SymPy's LagrangesMethod.

For each .lag model with constraints (docs/language.md, *Constraints*; also inputs at their
defaults, forces and a Rayleigh function, as generalized forces in LagrangesMethod's
forcelist), SymPy's
sympy.physics.mechanics.LagrangesMethod with hol_coneqs (constraints free of velocities)
and nonhol_coneqs (the others) gives the augmented mass matrix and forcing of (q'', lambda);
solved at random states (on the constraint manifold or not: neither side stabilizes), they
must agree with q'' and lambda of the generated accelerations_and_multipliers (through
sympy_probe, default parameters). SymPy's multipliers follow the same convention
(M q'' = f + G^T lambda); SymPy lists the holonomic rows first.
Exit 0: agree; 1: disagree, or SymPy missing (install python3-sympy; never skipped).
Catches: a wrong G or gamma (a dropped dphi/dt, a nonholonomic row treated as holonomic),
a wrong KKT solve, multipliers in the wrong order or with the wrong sign.
usage: sympy_constraints.py SYMPY_PROBE MODEL.lag...
"""
import os
import random
import re
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sympy_check import evaluate, statements, t  # noqa: E402  (exits 1 without SymPy)
import sympy as sp  # noqa: E402
from sympy.physics.mechanics import LagrangesMethod, Point, ReferenceFrame  # noqa: E402


def read(path):
    coords, env, defaults, hol, nonhol, order = [], {}, {}, [], [], []
    name, L, R, forces = None, 0, 0, {}
    for st in statements(path):
        kw, _, rest = st.partition(' ')
        if kw == 'model':
            name = rest.strip()
        elif kw == 'coordinates':
            for c in [n.strip() for n in rest.split(',')]:
                env[c] = sp.Function(c)(t)
                coords.append(env[c])
        elif kw in ('parameters', 'input'):
            for item in re.split(r',(?![^(]*\))', rest):
                pname, _, value = item.partition('=')
                pname = pname.strip()
                env[pname] = sp.Symbol(pname)
                defaults[env[pname]] = sp.sympify(evaluate(value, env)).subs(defaults)
        elif kw == 'let':
            n, _, value = rest.partition('=')
            env[n.strip()] = evaluate(value, env)
        elif kw == 'lagrangian':
            L = evaluate(rest, env)
        elif kw == 'dissipation':
            R = evaluate(rest, env)
        elif kw == 'force':
            fname, _, value = rest.partition('=')
            forces[fname.strip()] = evaluate(value, env)
        elif kw == 'constraint':
            cname, _, eq = rest.partition(':')
            a, _, b = eq.partition('=')
            phi = evaluate(a, env) - evaluate(b, env)
            velocity = any(phi.has(sp.diff(q, t)) for q in coords)
            (nonhol if velocity else hol).append(phi)
            order.append(('n' if velocity else 'h', len(nonhol if velocity else hol) - 1))
    # generalized forces Q_i - dR/dq_i' as forces on points that move with q_i' along N.x
    # (partial velocity 1 for q_i, 0 for the others): LagrangesMethod's forcelist
    N = ReferenceFrame('N')
    forcelist = []
    for i, q in enumerate(coords):
        Q = forces.get(str(q.func), 0) - sp.diff(R, sp.diff(q, t))
        if Q != 0:
            P = Point('P%d' % i)
            P.set_vel(N, sp.diff(q, t) * N.x)
            forcelist.append((P, Q * N.x))
    return dict(name=name, coords=coords, defaults=defaults, L=L, hol=hol, nonhol=nonhol, order=order,
                forcelist=forcelist, frame=N)


def main():
    probe, models = sys.argv[1], sys.argv[2:]
    rng = random.Random(13)
    failures = 0
    for path in models:
        d = read(path)
        coords, n = d['coords'], len(d['coords'])
        lm = LagrangesMethod(d['L'], coords, hol_coneqs=d['hol'] or None, nonhol_coneqs=d['nonhol'] or None,
                             forcelist=d['forcelist'] or None, frame=d['frame'])
        lm.form_lagranges_equations()
        MM, F = lm.mass_matrix_full.subs(d['defaults']), lm.forcing_full.subs(d['defaults'])  # (q', q'', lambda)
        m = len(d['order'])
        states = [(rng.uniform(0, 2), [rng.uniform(-1.5, 1.5) for _ in coords], [rng.uniform(-1.5, 1.5) for _ in coords])
                  for _ in range(6)]
        text = ''.join('%r %s %s\n' % (tt, ' '.join(map(repr, qv)), ' '.join(map(repr, vv))) for tt, qv, vv in states)
        out = subprocess.run([probe, d['name']], input=text, check=True, capture_output=True, text=True).stdout
        rows = [list(map(float, line.split())) for line in out.splitlines()]
        before = failures
        if len(rows) != len(states) or any(len(r) != 2 * n + 1 + m for r in rows):
            print('%s: sympy_probe answered %r' % (path, out)); failures += 1
            rows = []
        nh = len(d['hol'])
        for (tt, qv, vv), row in zip(states, rows):
            sub = {sp.diff(q, t): v for q, v in zip(coords, vv)}
            sub2 = {q: x for q, x in zip(coords, qv)}
            A = MM.subs(sub).subs(sub2).subs(t, tt).evalf()
            b = F.subs(sub).subs(sub2).subs(t, tt).evalf()
            x = A.LUsolve(b)
            for i in range(n):
                a, g = float(x[n + i]), row[i]
                if abs(a - g) > 1e-8 * (1 + abs(a)):
                    print("%s: q''(%d) differs at t=%r: sympy %r, phynjo %r" % (path, i + 1, tt, a, g)); failures += 1
            for k, (kind, j) in enumerate(d['order']):
                a = float(x[2 * n + (j if kind == 'h' else nh + j)])
                g = row[2 * n + 1 + k]
                if abs(a - g) > 1e-8 * (1 + abs(a)):
                    print('%s: lambda(%d) differs at t=%r: sympy %r, phynjo %r' % (path, k + 1, tt, a, g)); failures += 1
        print("%s: q'' and lambda at 6 random states %s SymPy's LagrangesMethod (%d holonomic, %d nonholonomic)"
              % (path, 'agree with' if failures == before else 'DISAGREE with', nh, len(d['nonhol'])))
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
