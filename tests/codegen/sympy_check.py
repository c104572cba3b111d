#!/usr/bin/env python3
"""Independent check of phynjo-lagc's equations of motion with SymPy.

Reads a .lag model (the subset the examples use: model, coordinates, parameters, let,
lagrangian, dissipation, force; primes on names) and derives M and f with SymPy from the
Euler-Lagrange equations, the momenta p = dL/dq' and the energy E = sum q' p - L.
- M and f: `phynjo-lagc --emit=eom`, compared at random points (parameters included);
- q'', p and E: the generated code (sympy_probe, the models at their default parameters),
  compared at random states with SymPy's own solve of M q'' = f.
Exit 0: agree; 1: disagree, or SymPy missing (install python3-sympy; never skipped).
Catches: a wrong M or f in the derivation, a wrong solve in the emitted `accelerations`,
wrong emitted momenta or energy.
usage: sympy_check.py PHYNJO_LAGC SYMPY_PROBE MODEL.lag...
"""
import random
import re
import subprocess
import sys

try:
    import sympy as sp
except ImportError:
    print('SymPy is not installed for %s: apt-get install python3-sympy (scripts/install-deps does)' % sys.executable)
    sys.exit(1)

t = sp.Symbol('t')

# The functions of docs/language.md as SymPy's own: abs and sign are SymPy's Abs and
# sign, atan2(y, x) is SymPy's atan2 (the same argument order).
FUNCTIONS = dict(sin=sp.sin, cos=sp.cos, tan=sp.tan, exp=sp.exp, log=sp.log, sqrt=sp.sqrt,
                 asin=sp.asin, acos=sp.acos, atan=sp.atan, atan2=sp.atan2, sinh=sp.sinh, cosh=sp.cosh,
                 tanh=sp.tanh, abs=sp.Abs, sign=sp.sign)


def to_python(expr):
    """The .lag expression syntax as a Python expression over the names in `env`."""
    expr = expr.replace('^', '**')
    return re.sub(r"([A-Za-z_][A-Za-z0-9_]*)'", r"D(\1)", expr)


def statements(path):
    """The statements of a .lag file: lines joined inside parentheses, comments dropped."""
    out, depth, cur = [], 0, ''
    for line in open(path).read().splitlines():
        line = line.split('#')[0]
        cur += ' ' + line
        depth += line.count('(') - line.count(')')
        if depth == 0:
            if cur.strip():
                out.append(cur.strip())
            cur = ''
    return out


def derive(path):
    coords, params, env, defaults = [], {}, {}, {}
    L = R = 0
    model_name = None
    forces = {}
    for st in statements(path):
        kw, _, rest = st.partition(' ')
        if kw == 'model':
            model_name = rest.strip()
        elif kw == 'coordinates':
            for cname in [n.strip() for n in rest.split(',')]:
                f = sp.Function(cname)(t)
                coords.append(f)
                env[cname] = f
        elif kw == 'parameters':
            for item in re.split(r',(?![^(]*\))', rest):
                pname, _, value = item.partition('=')
                pname = pname.strip()
                env[pname] = sp.Symbol(pname)
                params[pname] = env[pname]
                defaults[env[pname]] = sp.sympify(evaluate(value, env)).subs(defaults)
        elif kw == 'let':
            name, _, value = rest.partition('=')
            env[name.strip()] = evaluate(value, env)
        elif kw == 'lagrangian':
            L = evaluate(rest, env)
        elif kw == 'dissipation':
            R = evaluate(rest, env)
        elif kw == 'force':
            name, _, value = rest.partition('=')
            forces[name.strip()] = evaluate(value, env)
    qd = [sp.diff(q, t) for q in coords]
    qdd = [sp.diff(q, t, 2) for q in coords]
    n = len(coords)
    el = []
    for i, q in enumerate(coords):
        Q = forces.get(str(q.func), 0)
        el.append(sp.diff(sp.diff(L, qd[i]), t) - sp.diff(L, q) - Q + sp.diff(R, qd[i]))
    M = [[sp.diff(el[i], qdd[j]) for j in range(n)] for i in range(n)]
    zero = {a: 0 for a in qdd}
    f = [-el[i].subs(zero) for i in range(n)]
    p = [sp.diff(L, qd[i]) for i in range(n)]
    E = sum(qd[i] * p[i] for i in range(n)) - L
    return dict(name=model_name, coords=coords, params=params, defaults=defaults, M=M, f=f, p=p, E=E)


def evaluate(expr, env):
    def D(e):
        return sp.diff(e, t)
    scope = dict(env, D=D, pi=sp.pi, t=t, **FUNCTIONS)
    return eval(to_python(expr), {'__builtins__': {}}, scope)


def phynjo_eom(lagc, path, coords, params):
    out = subprocess.run([lagc, path, '--emit=eom'], check=True, capture_output=True, text=True).stdout
    names = {str(q.func): sp.Symbol('q_' + str(q.func)) for q in coords}
    scope = {k: sp.Symbol(k) for k in params}
    scope.update(names)
    M, f = {}, {}
    for line in out.splitlines():
        if line.startswith('#'):
            continue
        lhs, _, rhs = line.partition(' = ')
        py = rhs.replace('^', '**')
        py = re.sub(r"([A-Za-z_][A-Za-z0-9_]*)'", r"\1_dot", py)
        local = dict(scope)
        for q in coords:
            local[str(q.func) + '_dot'] = sp.Symbol('v_' + str(q.func))
        local.update(pi=sp.pi, t=t, **FUNCTIONS)
        value = eval(py, {'__builtins__': {}}, local)
        idx = tuple(int(k) - 1 for k in lhs[2:-1].split(','))
        (M if lhs.startswith('M') else f)[idx if len(idx) == 2 else idx[0]] = value
    return M, f


def close(a, b, tol=1e-9):
    return abs(a - b) <= tol * (1 + abs(a))


def main():
    lagc, probe, models = sys.argv[1], sys.argv[2], sys.argv[3:]
    rng = random.Random(7)
    failures = 0
    failed_models = 0
    for path in models:
        before = failures
        d = derive(path)
        coords, params, M, f = d['coords'], d['params'], d['M'], d['f']
        Mp, fp = phynjo_eom(lagc, path, coords, params)
        n = len(coords)

        def sympy_value(e, qv, vv, point):
            e = e.subs({sp.diff(q, t): vv[q] for q in coords}).subs(qv).subs(point)
            return float(e)

        for trial in range(4):
            point = {p: rng.uniform(0.5, 2) for p in params.values()}
            qv = {q: rng.uniform(-1.5, 1.5) for q in coords}
            vv = {q: rng.uniform(-1.5, 1.5) for q in coords}
            point[t] = rng.uniform(0, 2)
            def phynjo_value(e):
                sub = {sp.Symbol('q_' + str(q.func)): qv[q] for q in coords}
                sub.update({sp.Symbol('v_' + str(q.func)): vv[q] for q in coords})
                sub.update({sp.Symbol(str(k)): v for k, v in point.items()})
                return float(sp.sympify(e).subs(sub))
            for i in range(n):
                for j in range(n):
                    a, b = sympy_value(M[i][j], qv, vv, point), phynjo_value(Mp[(i, j)])
                    if not close(a, b):
                        print('%s: M(%d,%d) differs: sympy %r, phynjo %r' % (path, i + 1, j + 1, a, b)); failures += 1
                a, b = sympy_value(f[i], qv, vv, point), phynjo_value(fp[i])
                if not close(a, b):
                    print('%s: f(%d) differs: sympy %r, phynjo %r' % (path, i + 1, a, b)); failures += 1

        # q'', p, E of the generated code at the default parameters
        states = []
        for trial in range(6):
            tt = rng.uniform(0, 2)
            qv = {q: rng.uniform(-1.5, 1.5) for q in coords}
            vv = {q: rng.uniform(-1.5, 1.5) for q in coords}
            states.append((tt, qv, vv))
        text = ''.join('%r %s %s\n' % (tt, ' '.join(repr(qv[q]) for q in coords), ' '.join(repr(vv[q]) for q in coords))
                       for tt, qv, vv in states)
        out = subprocess.run([probe, d['name']], input=text, check=True, capture_output=True, text=True).stdout
        rows = [list(map(float, line.split())) for line in out.splitlines()]
        if len(rows) != len(states):
            print('%s: sympy_probe answered %d states of %d' % (path, len(rows), len(states))); failures += 1
        for (tt, qv, vv), row in zip(states, rows):
            point = dict(d['defaults'])
            point[t] = tt
            Mn = sp.Matrix(n, n, lambda i, j: sympy_value(M[i][j], qv, vv, point))
            fn = sp.Matrix(n, 1, lambda i, j: sympy_value(f[i], qv, vv, point))
            acc = Mn.LUsolve(fn)
            for i in range(n):
                if not close(float(acc[i]), row[i], 1e-8):
                    print("%s: q''(%d) differs at t=%r: sympy %r, phynjo %r" % (path, i + 1, tt, float(acc[i]), row[i])); failures += 1
                pi = sympy_value(d['p'][i], qv, vv, point)
                if not close(pi, row[n + i]):
                    print('%s: p(%d) differs: sympy %r, phynjo %r' % (path, i + 1, pi, row[n + i])); failures += 1
            E = sympy_value(d['E'], qv, vv, point)
            if not close(E, row[2 * n]):
                print('%s: E differs: sympy %r, phynjo %r' % (path, E, row[2 * n])); failures += 1
        ok = failures == before
        failed_models += 0 if ok else 1
        print("%s: M and f at 4 random points, q'', p and E at 6 random states %s SymPy"
              % (path, 'agree with' if ok else 'DISAGREE with'))
    print('%d models agree, %d disagree' % (len(models) - failed_models, failed_models))
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
