#!/usr/bin/env python3
"""SymPy reference for bench_constrained: the same job as `phynjo-lagc` on the N-link
pendulum in Cartesian coordinates (2N coordinates x_i, y_i, N rod constraints).

SymPy's LagrangesMethod on the same Lagrangian with hol_coneqs (the rods), its
mass_matrix_full and forcing_full, common subexpression elimination (sympy.cse) and C code
for every entry (sympy.ccode). Prints the seconds taken and the operation count.

usage: sympy_constrained_compile.py N
"""
import os
import sys
import time

import sympy as sp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sympy_nlink_compile import c_code  # noqa: E402  (the same cse and C printing)


def main():
    n = int(sys.argv[1])
    start = time.perf_counter()
    t = dynamicsymbols._t
    xs = dynamicsymbols('x1:%d' % (n + 1))
    ys = dynamicsymbols('y1:%d' % (n + 1))
    ms = sp.symbols('m1:%d' % (n + 1))
    ls = sp.symbols('l1:%d' % (n + 1))
    g = sp.Symbol('g')
    L = sum(ms[i] / 2 * (xs[i].diff(t) ** 2 + ys[i].diff(t) ** 2) for i in range(n)) - g * sum(ms[i] * ys[i] for i in range(n))
    rods = [xs[0] ** 2 + ys[0] ** 2 - ls[0] ** 2]
    rods += [(xs[i] - xs[i - 1]) ** 2 + (ys[i] - ys[i - 1]) ** 2 - ls[i] ** 2 for i in range(1, n)]
    qs = [c for i in range(n) for c in (xs[i], ys[i])]
    lm = LagrangesMethod(L, qs, hol_coneqs=rods)
    lm.form_lagranges_equations()
    M = lm.mass_matrix_full
    f = lm.forcing_full
    elapsed, ops, chars = c_code(M, f, start)
    print('seconds %.6f' % elapsed)
    print('ops %d' % ops)
    print('code_chars %d' % chars)


if __name__ == '__main__':
    main()
