#!/usr/bin/env python3
"""Independent check of phynjo-lagc's equations of motion with SymPy.

Reads a .lag model (the subset the examples use: coordinates, parameters, let, lagrangian,
dissipation, force; primes on names), derives M and f with SymPy from the Euler-Lagrange
equations, runs `phynjo-lagc --emit=eom`, and compares both numerically at random points.
Exit 0: agree; 1: disagree; 77: SymPy not available (ctest reports the test as skipped).
usage: sympy_check.py PHYNJO_LAGC MODEL.lag...
"""
import random
import re
import subprocess
import sys

try:
    import sympy as sp
except ImportError:
    print('SymPy not available: skipped')
    sys.exit(77)

t = sp.Symbol('t')


def to_python(expr):
    """The .lag expression syntax as a Python expression over the names in `env`."""
    expr = expr.replace('^', '**')
    return re.sub(r"([A-Za-z_][A-Za-z0-9_]*)'", r"D(\1)", expr)


def derive(path):
    text = open(path).read()
    # join lines inside parentheses, drop comments
    statements, depth, cur = [], 0, ''
    for line in text.splitlines():
        line = line.split('#')[0]
        cur += ' ' + line
        depth += line.count('(') - line.count(')')
        if depth == 0:
            if cur.strip():
                statements.append(cur.strip())
            cur = ''
    coords, params, env = [], {}, {}
    L = R = 0
    forces = {}
    for st in statements:
        kw, _, rest = st.partition(' ')
        if kw == 'coordinates':
            for name in [n.strip() for n in rest.split(',')]:
                f = sp.Function(name)(t)
                coords.append(f)
                env[name] = f
        elif kw == 'parameters':
            for item in re.split(r',(?![^(]*\))', rest):
                name = item.split('=')[0].strip()
                env[name] = sp.Symbol(name)
                params[name] = env[name]
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
    return coords, params, M, f


def evaluate(expr, env):
    def D(e):
        return sp.diff(e, t)
    scope = dict(env, D=D, sin=sp.sin, cos=sp.cos, tan=sp.tan, exp=sp.exp, log=sp.log, sqrt=sp.sqrt, pi=sp.pi, t=t)
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
        local.update(sin=sp.sin, cos=sp.cos, tan=sp.tan, exp=sp.exp, log=sp.log, sqrt=sp.sqrt, pi=sp.pi, t=t)
        value = eval(py, {'__builtins__': {}}, local)
        idx = tuple(int(k) - 1 for k in lhs[2:-1].split(','))
        (M if lhs.startswith('M') else f)[idx if len(idx) == 2 else idx[0]] = value
    return M, f


def main():
    lagc, models = sys.argv[1], sys.argv[2:]
    rng = random.Random(7)
    failures = 0
    failed_models = 0
    for path in models:
        before = failures
        coords, params, M, f = derive(path)
        Mp, fp = phynjo_eom(lagc, path, coords, params)
        n = len(coords)
        for trial in range(4):
            point = {p: rng.uniform(0.5, 2) for p in params.values()}
            qv = {q: rng.uniform(-1.5, 1.5) for q in coords}
            vv = {q: rng.uniform(-1.5, 1.5) for q in coords}
            point[t] = rng.uniform(0, 2)
            def sympy_value(e):
                e = e.subs({sp.diff(q, t): vv[q] for q in coords}).subs(qv).subs(point)
                return float(e)
            def phynjo_value(e):
                sub = {sp.Symbol('q_' + str(q.func)): qv[q] for q in coords}
                sub.update({sp.Symbol('v_' + str(q.func)): vv[q] for q in coords})
                sub.update({sp.Symbol(str(k)): v for k, v in point.items()})
                return float(sp.sympify(e).subs(sub))
            for i in range(n):
                for j in range(n):
                    a, b = sympy_value(M[i][j]), phynjo_value(Mp[(i, j)])
                    if abs(a - b) > 1e-9 * (1 + abs(a)):
                        print('%s: M(%d,%d) differs: sympy %r, phynjo %r' % (path, i + 1, j + 1, a, b)); failures += 1
                a, b = sympy_value(f[i]), phynjo_value(fp[i])
                if abs(a - b) > 1e-9 * (1 + abs(a)):
                    print('%s: f(%d) differs: sympy %r, phynjo %r' % (path, i + 1, a, b)); failures += 1
        ok = failures == before
        failed_models += 0 if ok else 1
        print('%s: M and f %s SymPy at 4 random points' % (path, 'agree with' if ok else 'DISAGREE with'))
    print('%d passed, %d failed' % (len(models) - failed_models, failed_models))
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
