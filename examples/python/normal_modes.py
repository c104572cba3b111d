#!/usr/bin/env python3
"""The double pendulum's normal modes from Python (docs/python.md): the model compiled from
examples/models/double_pendulum.lag, linearized at rest (exact Jacobians), then a small run
started in the slow mode — its swing frequency measured against the eigenvalue.
    usage: PYTHONPATH=BUILD/python python3 examples/python/normal_modes.py [OUT_DIR]"""
import os
import sys

import numpy as np

import phynjo

out = sys.argv[1] if len(sys.argv) > 1 else "demo-output"
here = os.path.dirname(os.path.abspath(__file__))
m = phynjo.compile(os.path.join(here, "..", "models", "double_pendulum.lag"))
print(f"python: compiled {m.name} ({'from the cache' if m.cache_hit else f'in {m.compile_seconds:.2f} s'})")

lin = m.linearize(at={"th1": 0, "th2": 0})
slow, fast = np.sort(np.abs(lin.eigenvalues.imag))[::2]
print(f"python: normal modes at rest: {slow:.6f} and {fast:.6f} rad/s (exact: sqrt(g (2 -+ sqrt 2)))")

# the slow mode's shape: th2 = sqrt(2) th1 (equal masses and lengths)
a = 0.01
r = m.simulate(t_end=20, dt=1e-3, integrator="dopri", rtol=1e-11, atol=1e-13,
               initial={"th1": a, "th2": a * np.sqrt(2)})
th1 = r.q[:, 0]
k = np.nonzero((th1[:-1] < 0) & (th1[1:] >= 0))[0]          # upward zero crossings
crossings = r.t[k] - th1[k] * (r.t[k + 1] - r.t[k]) / (th1[k + 1] - th1[k])
w = 2 * np.pi * (len(crossings) - 1) / (crossings[-1] - crossings[0])
print(f"python: a {a} rad run in the slow mode swings at {w:.6f} rad/s "
      f"(relative difference {abs(w - slow) / slow:.1e}; {len(crossings)} swings; max energy error {r.max_energy_error:.1e})")

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("python: (matplotlib not found: no picture)")
    sys.exit(0)
fig, ax = plt.subplots(figsize=(9, 4))
ax.plot(r.t, r.q[:, 0], label="th1")
ax.plot(r.t, r.q[:, 1], label="th2")
ax.plot(r.t, r.q[:, 1] / np.sqrt(2), "k:", lw=0.8, label="th2 / sqrt 2")
ax.set_xlabel("t / s")
ax.set_ylabel("angle / rad")
ax.set_title(f"Double pendulum in its slow normal mode: {w:.5f} rad/s measured, {slow:.5f} rad/s from linearize")
ax.legend(loc="upper right")
fig.tight_layout()
os.makedirs(out, exist_ok=True)
path = os.path.join(out, "python_normal_modes.png")
fig.savefig(path, dpi=100)
print(f"python: picture: {path}")
