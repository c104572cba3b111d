#!/usr/bin/env python3
"""The stiff chain of N masses (examples/models/stiff_chain.lag for N = 3,
bench/stiff_chain_30.lag for N = 30) the way a SciPy user integrates it:
SymPy derives the Euler-Lagrange equations (with the Rayleigh dissipation) and their
Jacobian, lambdify makes NumPy functions of them, solve_ivp(method='BDF', jac=...) integrates
0..T at the given tolerances. Prints `seconds S` (the integration only, best of 3), the
step count and the final state.
    usage: scipy_stiff_chain.py N [T] [RTOL] [ATOL]"""
import sys
import time

import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp

n = int(sys.argv[1]) if len(sys.argv) > 1 else 3
T = float(sys.argv[2]) if len(sys.argv) > 2 else 20.0
rtol = float(sys.argv[3]) if len(sys.argv) > 3 else 1e-8
atol = float(sys.argv[4]) if len(sys.argv) > 4 else 1e-10

m, k1, c1, k = 1.0, 1e6, 2000.0, 1.0
q = sp.symbols("x1:%d" % (n + 1))
v = sp.symbols("v1:%d" % (n + 1))
a = sp.symbols("a1:%d" % (n + 1))
L = sp.Rational(1, 2) * m * sum(vi**2 for vi in v) - sp.Rational(1, 2) * k1 * q[0]**2 \
    - sum(sp.Rational(1, 2) * k * (q[i + 1] - q[i])**2 for i in range(n - 1))
if n == 3:  # examples/models/stiff_chain.lag
    x0 = [0.0, 0.5, 1.0]
else:       # bench/stiff_chain_N.lag
    x0 = [i / n for i in range(n)]
R = sp.Rational(1, 2) * c1 * v[0]**2
# d/dt dL/dv_i = sum_j d2L/dv_i dv_j a_j + d2L/dv_i dq_j v_j
eqs = []
for i in range(n):
    p = sp.diff(L, v[i])
    dt_p = sum(sp.diff(p, v[j]) * a[j] + sp.diff(p, q[j]) * v[j] for j in range(n))
    eqs.append(sp.Eq(dt_p - sp.diff(L, q[i]) + sp.diff(R, v[i]), 0))
sol = sp.solve(eqs, a, dict=True)[0]
y = list(q) + list(v)
rhs = sp.Matrix(list(v) + [sol[ai] for ai in a])
jac = rhs.jacobian(y)
f = sp.lambdify([y], list(rhs), "numpy")
J = sp.lambdify([y], jac, "numpy")
fun = lambda t, yy: np.asarray(f(yy), dtype=float)
jfun = lambda t, yy: np.asarray(J(yy), dtype=float)
y0 = np.array(x0 + [0.0] * n)
best = 1e300
for _ in range(3):
    t0 = time.perf_counter()
    r = solve_ivp(fun, (0.0, T), y0, method="BDF", jac=jfun, rtol=rtol, atol=atol)
    best = min(best, time.perf_counter() - t0)
print("seconds %.6f" % best)
print("steps %d" % (len(r.t) - 1))
print("final " + " ".join("%.10g" % x for x in r.y[:3, -1]))  # x1, x2, x3
