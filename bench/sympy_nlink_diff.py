#!/usr/bin/env python3
"""SymPy reference for bench_cas_diff: differentiate the n-link pendulum-on-cart Lagrangian
(the system of examples/models/nlink_cart.py and sympy.physics.mechanics.models.
n_link_pendulum_on_cart) -- for every coordinate q_i: dL/dq_i', dL/dq_i and d/dt(dL/dq_i').

Two ways, both timed, the faster is the reference:
  dynamic: q_i(t) as dynamicsymbols, .diff(qd) / .diff(q) / .diff(t)   (what LagrangesMethod does)
  plain:   q_i, u_i, a_i plain symbols, d/dt p = sum dp/dq_j u_j + dp/du_j a_j
SymPy's cache is cleared before every repetition, and the Lagrangian is built outside the timing.

usage: sympy_nlink_diff.py N REPS   ->  prints "dynamic SECONDS", "plain SECONDS" (best of REPS)
"""
import sys
import time

import sympy as sp
from sympy.core.cache import clear_cache
from sympy.physics.mechanics import dynamicsymbols


def lagrangian(n, plain):
    g = sp.Symbol('g')
    m = sp.symbols('m0:%d' % (n + 1))
    l = sp.symbols('l1:%d' % (n + 1))
    t = sp.Symbol('t')
    if plain:
        q = sp.symbols('q0:%d' % (n + 1))
        u = sp.symbols('u0:%d' % (n + 1))
        a = sp.symbols('a0:%d' % (n + 1))
        def ddt(e):
            return sum(e.diff(q[j]) * u[j] for j in range(n + 1))
    else:
        q = dynamicsymbols('q0:%d' % (n + 1))
        u = [qi.diff(t) for qi in q]
        a = None
        def ddt(e):
            return e.diff(t)
    x, y = [q[0]], [sp.S(0)]
    for i in range(1, n + 1):
        x.append(x[-1] - l[i - 1] * sp.sin(q[i]))
        y.append(y[-1] + l[i - 1] * sp.cos(q[i]))
    L = sum(sp.Rational(1, 2) * m[i] * (ddt(x[i]) ** 2 + ddt(y[i]) ** 2) for i in range(n + 1)) \
        - g * sum(m[i] * y[i] for i in range(n + 1))
    return L, q, u, a, t


def point(n):
    """The numeric point at which both sides evaluate their results (the agreement check)."""
    v = {'g': 9.81}
    for i in range(n + 1):
        v['q%d' % i] = 0.1 * (i + 1)
        v['u%d' % i] = 0.2 - 0.03 * i
        v['a%d' % i] = 0.3 + 0.01 * i
        v['m%d' % i] = 1.0 + 0.1 * i
        if i:
            v['l%d' % i] = 1.0 - 0.01 * i
    return v


def work(n, plain, check=False):
    L, q, u, a, t = lagrangian(n, plain)
    start = time.perf_counter()
    out = []
    for i in range(n + 1):
        p = L.diff(u[i])
        dLdq = L.diff(q[i])
        if plain:
            dpdt = sum(p.diff(q[j]) * u[j] + p.diff(u[j]) * a[j] for j in range(n + 1))
        else:
            dpdt = p.diff(t)
        out += [p, dLdq, dpdt]
    elapsed = time.perf_counter() - start
    if check:  # sum of every result at the common point
        v = point(n)
        subs = {sym: v[sym.name] for e in out for sym in e.free_symbols if sym.name in v}
        total = sum(float(e.xreplace(subs)) for e in out)
        print('check %.15g' % total, flush=True)
    return elapsed


if __name__ == '__main__':
    n = int(sys.argv[1])
    reps = int(sys.argv[2]) if len(sys.argv) > 2 else 3
    for plain in (False, True):
        best = float('inf')
        for _ in range(reps):
            clear_cache()
            best = min(best, work(n, plain, check=plain and _ == 0))
        print('%s %.6f' % ('plain' if plain else 'dynamic', best), flush=True)
