#!/usr/bin/env python3
"""The Python package against what a Python user has without it, each pair measured in this run:

  ratio py_first_result_double_pendulum  SymPy LagrangesMethod + lambdify + solve_ivp(RK45,
      rtol = atol = 1e-9) for 10 s, from nothing (a fresh interpreter), over phynjo.compile
      (the kernel not in the cache: the quick kernel, -O0, the optimized one building in the
      background, which this bench lets finish before it measures anything else) + simulate
      (Dormand-Prince, the same tolerances), also from a fresh interpreter.
  ratio py_simulate_double_pendulum      the same solve_ivp with the right-hand side lambdified
      already, over m.simulate on a compiled model.
  ratio py_sweep_flipmap                 SciPy's flip-map runs per second (bench/scipy_flipmap.py,
      one thread) over m.sweep's (the flip map's sweep, rk4 at 1 ms, one thread, lanes).
  ratio py_batch_accelerations           C++ calling the kernel on 1e5 states
      (bench/python_kernel_reference.cpp) over m.accelerations on a (1e5, 2) array with out=.
  and the compiler's time for the double pendulum's kernel, quick and optimized (target: under 1 s).

usage: python_bench.py REFERENCE_PROGRAM SOURCE_DIR   (bench/run-all runs it as bench_python)"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

reference_program, source = sys.argv[1], sys.argv[2]
model = os.path.join(source, "examples", "models", "double_pendulum.lag")
flip = os.path.join(source, "examples", "models", "flip_pendulum.lag")
py = sys.executable
env = dict(os.environ)

SYMPY_FROM_NOTHING = r'''
import sys, time
import numpy as np, sympy as sp
from scipy.integrate import solve_ivp
from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols
t = sp.symbols("t")
th1, th2 = dynamicsymbols("th1 th2")
m1 = m2 = l1 = l2 = 1
g = sp.Rational(981, 100)
x1, y1 = l1 * sp.sin(th1), -l1 * sp.cos(th1)
x2, y2 = x1 + l2 * sp.sin(th2), y1 - l2 * sp.cos(th2)
L = sp.Rational(1, 2) * m1 * (x1.diff(t)**2 + y1.diff(t)**2) + sp.Rational(1, 2) * m2 * (x2.diff(t)**2 + y2.diff(t)**2) \
    - g * (m1 * y1 + m2 * y2)
lm = LagrangesMethod(L, [th1, th2])
lm.form_lagranges_equations()
rhs = lm.rhs()
q1, q2, w1, w2 = sp.symbols("q1 q2 w1 w2")
subs = {th1.diff(t): w1, th2.diff(t): w2, th1: q1, th2: q2}
f = sp.lambdify((q1, q2, w1, w2), [e.subs(subs) for e in rhs], "numpy")
fun = lambda _, y: f(*y)
t0 = time.perf_counter()
r = solve_ivp(fun, (0, 10), [np.pi / 2, np.pi / 2, 0, 0], method="RK45", rtol=1e-9, atol=1e-9, dense_output=False)
solve = time.perf_counter() - t0
if len(sys.argv) > 1:  # warm: the solve again, the right-hand side lambdified already
    for _ in range(3):
        t0 = time.perf_counter()
        solve_ivp(fun, (0, 10), [np.pi / 2, np.pi / 2, 0, 0], method="RK45", rtol=1e-9, atol=1e-9)
        solve = min(solve, time.perf_counter() - t0)
print("solve", solve, "steps", len(r.t), "end", r.y[0, -1])
'''

PHYNJO_FROM_NOTHING = r'''
import sys, phynjo
m = phynjo.compile(sys.argv[1], cache_dir=sys.argv[2], quick=len(sys.argv) < 4)
r = m.simulate(t_end=10, dt=0.01, integrator="dopri", rtol=1e-9, atol=1e-9)
print("compile", m.compile_seconds, "hit", m.cache_hit, "end", r.q[-1, 0])
'''


def wall(args, **kw):
    t0 = time.perf_counter()
    p = subprocess.run(args, capture_output=True, text=True, env=env, **kw)
    sec = time.perf_counter() - t0
    if p.returncode != 0:
        sys.exit(f"bench_python: {args[:3]} failed:\n{p.stderr}")
    return sec, p.stdout


def best(f, n=5):
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        f()
        out.append(time.perf_counter() - t0)
    return min(out)


with tempfile.TemporaryDirectory(prefix="phynjo-bench-") as tmp:
    # -- first result from nothing
    sympy_sec, sympy_out = min((wall([py, "-c", SYMPY_FROM_NOTHING]) for _ in range(3)), key=lambda r: r[0])
    cache = os.path.join(tmp, "cache")

    def settled():
        """Waits for the background builds of optimized kernels (they would share the cores)."""
        while any(f.endswith(".building") for f in os.listdir(os.path.join(cache, "kernels"))):
            time.sleep(0.05)

    def variant(k):
        path = os.path.join(tmp, f"dp{k}.lag")
        with open(model) as f, open(path, "w") as g:
            g.write(f.read() + f"\n# variant {k}: a text no cache holds\n")
        return path

    cold = []
    for k in range(3):
        cold.append(wall([py, "-c", PHYNJO_FROM_NOTHING, variant(k), cache]))
        settled()
    cold_sec, cold_out = min(cold, key=lambda r: r[0])
    quick_sec = float(cold_out.split()[1])
    optimized = [float(wall([py, "-c", PHYNJO_FROM_NOTHING, variant(10 + k), cache, "optimized"])[1].split()[1])
                 for k in range(3)]
    print(f"double pendulum, 10 s to rtol 1e-9 from a fresh interpreter:")
    print(f"  SymPy LagrangesMethod + lambdify + SciPy RK45: {sympy_sec:.3f} s   ({sympy_out.strip()})")
    print(f"  phynjo.compile (kernel not cached: the quick one) + simulate(dopri): {cold_sec:.3f} s   ({cold_out.strip()})")
    print(f"  kernel build of the double pendulum: quick (-O0) {quick_sec:.3f} s, optimized (-O2) {min(optimized):.3f} s "
          f"of compiler wall time (target < 1 s)")
    print(f"ratio py_first_result_double_pendulum = {sympy_sec / cold_sec:.2f}")

    # -- a warm solve
    import phynjo
    m = phynjo.compile(model, cache_dir=cache, quick=False)
    _, warm_out = wall([py, "-c", SYMPY_FROM_NOTHING, "warm"])
    scipy_solve = float(warm_out.split()[1])
    ours = best(lambda: m.simulate(t_end=10, dt=0.01, integrator="dopri", rtol=1e-9, atol=1e-9), 7)
    print(f"warm: SciPy solve_ivp {scipy_solve * 1e3:.2f} ms, m.simulate {ours * 1e3:.3f} ms")
    print(f"ratio py_simulate_double_pendulum = {scipy_solve / ours:.1f}")

    # -- the flip map's sweep
    _, out = wall([py, os.path.join(source, "bench", "scipy_flipmap.py"), "8"])
    scipy_rate = float(out.split()[-1])
    fm = phynjo.compile(flip, cache_dir=cache, quick=False)
    n = 64
    sweep_sec = best(lambda: fm.sweep(grid={"th1": (-3, 3, n), "th2": (-3, 3, n)}, t_end=10, dt=1e-3,
                                      integrator="rk4", threads=1), 3)
    rate = n * n / sweep_sec
    print(f"flip map: SciPy {scipy_rate:.2f} runs/s, m.sweep {rate:.1f} runs/s ({n}x{n}, one thread)")
    print(f"ratio py_sweep_flipmap = {rate / scipy_rate:.0f}")

    # -- batched accelerations against C++ on the same kernel
    N = 100000
    _, out = wall([reference_program, m.kernel_path, str(N)])
    cxx = float(out.split()[2])
    rng = np.random.default_rng(7)
    q = rng.uniform(-3, 3, (N, 2))
    qd = rng.uniform(-3, 3, (N, 2))
    a = np.empty((N, 2))
    ours = best(lambda: m.accelerations(q, qd, out=a), 7)
    print(f"1e5 accelerations: C++ {cxx * 1e3:.3f} ms, Python {ours * 1e3:.3f} ms")
    print(f"ratio py_batch_accelerations = {cxx / ours:.2f}")
