#!/usr/bin/env python3
"""The flip map's reference in Python: the double pendulum's equations derived by SymPy
(LagrangesMethod), lambdified, and integrated by SciPy's solve_ivp (RK45, rtol = atol = 1e-10,
terminal events at |th| = pi, 10 s cap) over an N x N grid of [-3, 3]^2 released from rest.
Prints `scipy trajectories/s R` (bench/bench_ensemble.cpp reads it). Usage: scipy_flipmap.py N"""
import sys, time
import numpy as np
import sympy as sp
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols

n = int(sys.argv[1]) if len(sys.argv) > 1 else 8
t = sp.symbols('t')
th1, th2 = dynamicsymbols('th1 th2')
m1 = m2 = l1 = l2 = 1
g = 9.81
x1, y1 = l1 * sp.sin(th1), -l1 * sp.cos(th1)
x2, y2 = x1 + l2 * sp.sin(th2), y1 - l2 * sp.cos(th2)
T = sp.Rational(1, 2) * m1 * (sp.diff(x1, t)**2 + sp.diff(y1, t)**2) + sp.Rational(1, 2) * m2 * (sp.diff(x2, t)**2 + sp.diff(y2, t)**2)
V = g * (m1 * y1 + m2 * y2)
lm = LagrangesMethod(T - V, [th1, th2])
lm.form_lagranges_equations()
rhs = lm.rhs()
w1, w2 = sp.symbols('w1 w2')
q1, q2 = sp.symbols('q1 q2')
subs = {sp.diff(th1, t): w1, sp.diff(th2, t): w2, th1: q1, th2: q2}
f = sp.lambdify((q1, q2, w1, w2), [e.subs(subs) for e in rhs], 'numpy')

def fun(_, y):
    return f(*y)

events = []
for i in (0, 1):
    for s in (1, -1):
        ev = (lambda i, s: lambda _, y: y[i] - s * np.pi)(i, s)
        ev.terminal = True
        events.append(ev)

grid = np.linspace(-3, 3, n)
start = time.perf_counter()
for a in grid:
    for b in grid:
        solve_ivp(fun, (0, 10), [a, b, 0, 0], method='RK45', rtol=1e-10, atol=1e-10, events=events)
sec = time.perf_counter() - start
print(f"scipy trajectories/s {n * n / sec:.4f}")
