"""phynjo from Python (python/): every call against the C++ results — the CMake-built
simulators, bit for bit — against closed forms and SymPy. Each test says the bug it catches."""
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import pytest

from conftest import CACHE, model_path, run_simulator

G = 9.81


def csv_rows(text):
    """A simulator's CSV (header skipped) as an array of floats."""
    lines = [l for l in text.splitlines() if l and not l[0].isalpha() and not l.startswith("#")]
    return np.array([[float(v) for v in l.split(",")] for l in lines])


def g17(a):
    """Numbers as the simulator prints them (%.17g): a bit-for-bit comparison."""
    return ["%.17g" % v for v in np.ravel(a)]


def test_names_units_and_defaults(compile_model):
    """Catches: the model's description read wrongly from the kernel's table (names shifted,
    inputs among the parameters, units or defaults lost, events or constraints missing)."""
    dp = compile_model("double_pendulum.lag")
    assert dp.name == "double_pendulum" and dp.dof == 2
    assert dp.coordinates == ("th1", "th2")
    assert list(dp.parameters) == ["m1", "m2", "l1", "l2", "g"]
    assert dp.parameters["g"].default == 9.81 and dp.inputs == {}
    assert dp.shapes == ("rod1", "rod2", "bob1", "bob2")
    ball = compile_model("bouncing_ball.lag")
    assert ball.parameters["g"].unit == "m/s^2" and ball.parameters["m"].unit == "kg" and ball.parameters["e"].unit == ""
    assert [(e.name, e.direction, e.stops) for e in ball.events] == [("bounce", -1, False)]
    cp = compile_model("cart_pole_input.lag")
    assert list(cp.inputs) == ["F"] and "F" not in cp.parameters
    fb = compile_model("four_bar.lag")
    assert len(fb.constraints) >= 1 and all(c.holonomic for c in fb.constraints)
    assert "double_pendulum" in repr(dp)


def test_against_the_pendulum_by_hand(compile_model):
    """Catches: the wrong function behind a name, parameters not reaching the kernel, t or
    q' passed in the wrong slot: theta'' = -g/l sin(theta), E, p and M of the pendulum."""
    p = compile_model("pendulum.lag")
    th, w = 0.7, -1.3
    assert p.accelerations([th], [w])[0] == pytest.approx(-G * math.sin(th), rel=1e-15)
    assert p.accelerations([th], [w], l=2.0)[0] == pytest.approx(-G / 2 * math.sin(th), rel=1e-15)
    assert p.mass_matrix([th], m=3.0, l=2.0)[0, 0] == pytest.approx(12.0)
    assert p.energy([th], [w]) == pytest.approx(0.5 * w * w - G * math.cos(th), rel=1e-15)
    assert p.momenta([th], [w], m=2.0)[0] == pytest.approx(2.0 * w)
    assert p.forcing([th], [w])[0] == pytest.approx(-G * math.sin(th))
    J = p.rhs_jacobian([th], [w])
    assert np.allclose(J, [[0, 1], [-G * math.cos(th), 0]], rtol=1e-15, atol=0)
    q0, v0 = p.initial_state()
    assert q0.tolist() == [1.0] and v0.tolist() == [0.0]
    assert p.parameter("l") == 1.0 and p.parameter("l", l=3.0) == 3.0


def test_batched_over_leading_axes_with_out(compile_model):
    """Catches: a batch laid out wrongly (states mixed up, a stride of the wrong length), out=
    ignored or the results' shape wrong: every state of a (4, 5, 2) batch against one call each,
    bit for bit, and out= filled in place."""
    dp = compile_model("double_pendulum.lag")
    rng = np.random.default_rng(7)
    q = rng.uniform(-3, 3, (4, 5, 2))
    qd = rng.uniform(-2, 2, (4, 5, 2))
    A = dp.accelerations(q, qd, m2=1.5)
    M = dp.mass_matrix(q, qd)
    E = dp.energy(q, qd)
    J = dp.rhs_jacobian(q, qd)
    assert A.shape == (4, 5, 2) and M.shape == (4, 5, 2, 2) and E.shape == (4, 5) and J.shape == (4, 5, 4, 4)
    for i in range(4):
        for j in range(5):
            assert g17(A[i, j]) == g17(dp.accelerations(q[i, j], qd[i, j], m2=1.5))
            assert g17(M[i, j]) == g17(dp.mass_matrix(q[i, j], qd[i, j]))
            assert g17(E[i, j]) == g17(dp.energy(q[i, j], qd[i, j]))
            assert g17(J[i, j]) == g17(dp.rhs_jacobian(q[i, j], qd[i, j]))
    out = np.full((4, 5, 2), np.nan)
    r = dp.accelerations(q, qd, out=out, m2=1.5)
    assert r is out or np.shares_memory(r, out)
    assert g17(out) == g17(A)
    # M q'' = f at every state
    f = dp.forcing(q, qd)
    assert np.allclose(np.einsum("...ij,...j->...i", M, dp.accelerations(q, qd)), f, rtol=1e-12, atol=1e-12)


def test_simulate_is_the_simulators_run(compile_model):
    """Catches: simulate not the simulator's run (another integrator, step plan, parameters or
    initial values; rows dropped or repeated by `every`): its rows against the CMake-built
    double_pendulum_sim's --output, bit for bit, for rk4 and midpoint."""
    dp = compile_model("double_pendulum.lag")
    r = dp.simulate(t_end=2, dt=1e-3, integrator="rk4", every=7, params={"m2": 2.5}, initial={"th1": 0.3, "th2'": 1})
    ref = csv_rows(run_simulator("double_pendulum_sim", "--t-end", 2, "--dt", 0.001, "--every", 7, "--param", "m2=2.5",
                                 "--init", "th1=0.3,th2'=1"))
    assert r.rows.shape == ref.shape
    assert g17(r.rows) == g17(ref)
    assert r.status == "finished" and r.reason == "" and r.t_end == 2.0
    assert r.q.shape == (len(r.t), 2) and g17(r.energy) == g17(ref[:, -1])
    r2 = dp.simulate(t_end=1, dt=2e-3, integrator="midpoint")
    ref2 = csv_rows(run_simulator("double_pendulum_sim", "--t-end", 1, "--dt", 0.002, "--integrator", "midpoint", "--every", 1))
    assert g17(r2.rows) == g17(ref2)
    assert r2.max_energy_error == pytest.approx(np.max(np.abs(ref2[:, -1] - ref2[0, -1])) / max(1, abs(ref2[0, -1])))


def test_dopri_with_tolerances_and_the_event_log(compile_model, tmp_path):
    """Catches: rtol/atol not reaching Dormand-Prince, the event log missing, wrong or out of
    order: the bouncing ball's impacts against the simulator's --events and the closed form
    of the first impact, sqrt(2h/g); a looser tolerance gives other (worse) bits."""
    ball = compile_model("bouncing_ball.lag")
    r = ball.simulate(t_end=3, dt=1e-3, integrator="dopri", rtol=1e-10, atol=1e-12)
    ev = tmp_path / "ev.csv"
    out = run_simulator("bouncing_ball_sim", "--t-end", 3, "--dt", 0.001, "--integrator", "dopri", "--rtol", 1e-10,
                        "--atol", 1e-12, "--events", ev, "--every", 1)
    assert g17(r.rows) == g17(csv_rows(out))
    ref = csv_rows(ev.read_text().replace("bounce", "0"))
    assert len(r.events) == len(ref) >= 5
    assert [e.name for e in r.events] == ["bounce"] * len(ref)
    assert g17([e.time for e in r.events]) == g17(ref[:, 0])
    assert g17([e.qd[0] for e in r.events]) == g17(ref[:, -1])
    assert r.events[0].time == pytest.approx(math.sqrt(2 / G), abs=1e-9)
    assert r.first_event == {"bounce": r.events[0].time}
    # free fall is a polynomial Dormand-Prince integrates exactly: the tolerances show on the
    # double pendulum's energy (rows 0.05 s apart: its steps are no longer than that)
    dp = compile_model("double_pendulum.lag")
    tight = dp.simulate(t_end=5, dt=0.05, integrator="dopri", rtol=1e-11, atol=1e-13)
    loose = dp.simulate(t_end=5, dt=0.05, integrator="dopri", rtol=1e-5, atol=1e-7)
    assert loose.max_energy_error > 1e3 * tight.max_energy_error and tight.max_energy_error < 1e-9


def test_linearize_against_the_normal_modes(compile_model):
    """Catches: A or B assembled wrongly (blocks swapped, the input's column lost), the
    eigenvalues of another matrix: the double pendulum's normal modes at rest,
    w^2 = (g/l)(2 -+ sqrt 2), and the cart-pole's B = (0, 0, 1/M, -1/(M l)) at the top."""
    dp = compile_model("double_pendulum.lag")
    lin = dp.linearize(at={"th1": 0, "th2": 0})
    w = np.sort(np.abs(lin.eigenvalues.imag))
    expect = np.sort(np.sqrt([G * (2 - math.sqrt(2)), G * (2 + math.sqrt(2))] * 2))
    assert np.allclose(w, expect, rtol=1e-12)
    assert np.allclose(lin.eigenvalues.real, 0, atol=1e-12) and not lin.stable
    assert lin.states == ("th1", "th2", "th1'", "th2'") and lin.B.shape == (4, 0)
    cp = compile_model("cart_pole_input.lag")
    lin = cp.linearize(at={"th": math.pi})
    assert lin.inputs == ("F",)
    assert lin.B[:, 0].tolist() == pytest.approx([0, 0, 1.0, 1.0 / 0.5], abs=1e-14)
    assert max(lin.eigenvalues.real) > 0  # the inverted pendulum is unstable


def test_sweep_is_the_simulators_summary(compile_model, tmp_path):
    """Catches: sweep's options not the CLI's (grid or Monte Carlo draws differ), the summary
    read wrongly (columns shifted, empty first-event cells not NaN, status or reason lost), a
    thread count that changes a row: against double_pendulum_sim --summary."""
    dp = compile_model("double_pendulum.lag")
    s = dp.sweep(grid={"th1": (0, 1, 3)}, uniform={"m2": (1, 2)}, samples=2, seed=5, t_end=0.5, threads=2)
    ref = tmp_path / "ref.csv"
    run_simulator("double_pendulum_sim", "--grid", "th1=0.0:1.0:3", "--uniform", "m2=1.0:2.0", "--samples", 2, "--seed", 5,
                  "--t-end", 0.5, "--dt", 0.001, "--integrator", "rk4", "--summary", ref)
    lines = [l.split(",") for l in ref.read_text().splitlines() if not l.startswith("#")]
    assert list(s.dtype.names) == lines[0]
    assert len(s) == len(lines) - 1 == 6
    for row, line in zip(s, lines[1:]):
        assert int(row["run"]) == int(line[0]) and row["status"] == line[lines[0].index("status")]
        for name, cell in zip(lines[0], line):
            if name not in ("run", "status", "reason"):
                assert "%.17g" % row[name] == "%.17g" % float(cell)
    assert set(s["status"]) == {"finished"}
    one = dp.sweep(grid={"th1": (0, 1, 3)}, uniform={"m2": (1, 2)}, samples=2, seed=5, t_end=0.5, threads=1)
    assert one.tobytes() == s.tobytes()
    ball = compile_model("bouncing_ball.lag")
    b = ball.sweep(grid={"h": (0.5, 1, 2)}, t_end=0.1)
    assert np.isnan(b["first_bounce"]).all() if "first_bounce" in b.dtype.names else True
    kept = tmp_path / "kept.csv"
    dp.sweep(grid={"th1": (0, 1, 2)}, t_end=0.1, summary=kept)
    assert kept.read_text().count("\n") >= 3


def test_equations_against_sympy_mechanics(compile_model):
    """Catches: M or f parsed into SymPy wrongly (a velocity taken for a coordinate, ^ or a
    function misread, entries transposed): the double pendulum's against SymPy mechanics'
    LagrangesMethod, derived independently here."""
    import sympy as sp
    from sympy.physics.mechanics import LagrangesMethod, dynamicsymbols
    dp = compile_model("double_pendulum.lag")
    M, f = dp.equations()
    t = sp.Symbol("t")
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    th1, th2 = sp.Function("th1")(t), sp.Function("th2")(t)
    x1, y1 = l1 * sp.sin(th1), -l1 * sp.cos(th1)
    x2, y2 = x1 + l2 * sp.sin(th2), y1 - l2 * sp.cos(th2)
    d = lambda e: sp.diff(e, t)
    L = sp.Rational(1, 2) * m1 * (d(x1) ** 2 + d(y1) ** 2) + sp.Rational(1, 2) * m2 * (d(x2) ** 2 + d(y2) ** 2) \
        - g * (m1 * y1 + m2 * y2)
    lm = LagrangesMethod(L, [th1, th2])
    lm.form_lagranges_equations()
    assert sp.simplify(M - lm.mass_matrix) == sp.zeros(2, 2)
    assert sp.simplify(f - lm.forcing) == sp.zeros(2, 1)
    tex = dp._repr_latex_()
    assert tex.startswith("$$\\begin{aligned}") and "M_{11} &=" in tex and "f_{2} &=" in tex
    assert "\\documentclass" in dp.latex()


def test_run_is_phynjo_run_and_plot(compile_model, tmp_path):
    """Catches: run() not the simulator's command line (output lost to the captured
    descriptors, the exit status dropped), plot() failing: --output against the CMake-built
    simulator's bytes, RunError with status 2 for a usage error, axes drawn."""
    dp = compile_model("double_pendulum.lag")
    out = tmp_path / "run.csv"
    text = dp.run("--t-end", 0.5, "--every", 9, "--output", out)
    assert text == ""
    assert out.read_text() == run_simulator("double_pendulum_sim", "--t-end", 0.5, "--every", 9)
    assert dp.run("--t-end", 0.01, "--every", 5) == run_simulator("double_pendulum_sim", "--t-end", 0.01, "--every", 5)
    import phynjo
    with pytest.raises(phynjo.RunError) as e:
        dp.run("--no-such-option")
    assert e.value.status == 2 and "--no-such-option" in str(e.value)
    import matplotlib
    matplotlib.use("Agg")
    axes = dp.simulate(t_end=1).plot()
    assert len(axes) == 2 and len(axes[0].lines) == 2


def test_cache_hit_corruption_and_two_processes(phynjo, tmp_path):
    """Catches: a cache that never hits, a corrupt kernel loaded (a crash) instead of rebuilt,
    two processes compiling one model at once corrupting each other's kernel."""
    cache = tmp_path / "cache"
    text = open(model_path("pendulum.lag")).read()
    a = phynjo.compile_string(text, "pendulum.lag", cache_dir=cache)
    b = phynjo.compile_string(text, "pendulum.lag", cache_dir=cache)
    assert not a.cache_hit and b.cache_hit and a.kernel_path == b.kernel_path and a.compile_seconds > 0
    # a byte changed (in a new file renamed over the kernel: this process has the old one
    # mapped): the checksum no longer matches
    data = bytearray(open(a.kernel_path, "rb").read())
    data[100] ^= 0xFF
    with open(a.kernel_path + ".bad", "wb") as f:
        f.write(data)
    os.replace(a.kernel_path + ".bad", a.kernel_path)
    c = phynjo.compile_string(text, "pendulum.lag", cache_dir=cache)
    assert not c.cache_hit and c.accelerations([1.0], [0.0])[0] == pytest.approx(-G * math.sin(1.0))
    d = phynjo.compile_string(text + "\n# another text, another kernel\n", "pendulum.lag", cache_dir=cache)
    assert not d.cache_hit and d.energy([0.0], [1.0]) == pytest.approx(0.5 - G)
    # two processes, a model no cache holds, at once
    fresh = tmp_path / "fresh"
    code = ("import sys, phynjo; m = phynjo.compile_string(open(sys.argv[1]).read(), 'dp.lag', cache_dir=sys.argv[2]);"
            "print(m.kernel_path, m.energy([0.5, 0.2], [0.1, 0.3]))")
    procs = [subprocess.Popen([sys.executable, "-c", code, model_path("double_pendulum.lag"), str(fresh)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _ in range(3)]
    outs = [p.communicate(timeout=300) for p in procs]
    assert all(p.returncode == 0 for p in procs), [o[1] for o in outs]
    assert len({o[0] for o in outs}) == 1
    assert not [f for f in os.listdir(fresh / "kernels") if f.endswith(".tmp")]


def test_model_errors_carry_file_line_column(phynjo, tmp_path):
    """Catches: a model error raised as a bare RuntimeError or losing where it is: ModelError
    with file, line, column and the caret line; a missing file; a missing compiler as
    BuildError saying what to install."""
    bad = tmp_path / "bad.lag"
    bad.write_text("model bad\ncoordinates x\nlagrangian 1/2*x'^2 - k*x^2\n")
    with pytest.raises(phynjo.ModelError) as e:
        phynjo.compile(bad, cache_dir=tmp_path / "c")
    assert (e.value.file, e.value.line) == (str(bad), 3) and e.value.column >= 1
    assert "k" in e.value.message and "^" in e.value.source_line
    assert str(e.value).startswith(f"{bad}:3:")
    with pytest.raises(phynjo.ModelError):
        phynjo.compile_string("model x\ncoordinates\n", cache_dir=tmp_path / "c")
    with pytest.raises(FileNotFoundError):
        phynjo.compile(tmp_path / "none.lag")
    env = dict(os.environ, CXX="/nonexistent/g++")
    code = ("import phynjo, sys\ntry:\n    phynjo.compile_string('model p\\ncoordinates x\\nlagrangian x\\'^2/2', cache_dir=sys.argv[1])\n"
            "except phynjo.BuildError as e:\n    print('BuildError:', e)\n")
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path / "nocxx")], env=env, capture_output=True, text=True)
    assert "BuildError: no C++ compiler" in r.stdout and "g++" in r.stdout, r.stdout + r.stderr


def test_hostile_inputs_raise_never_crash(compile_model, phynjo):
    """Catches: an interpreter crash or a silent NaN on bad input: wrong shapes (ValueError
    naming the expected shape), strings and objects for arrays, bad out=, unknown and
    non-finite parameters, bad run options, a singular mass matrix (the typed error)."""
    dp = compile_model("double_pendulum.lag")
    with pytest.raises(ValueError, match=r"\(\.\.\., 2\)"):
        dp.accelerations(np.zeros(3), np.zeros(3))
    with pytest.raises(ValueError, match="shape of q"):
        dp.accelerations(np.zeros((5, 2)), np.zeros((4, 2)))
    with pytest.raises(ValueError):
        dp.accelerations(np.zeros(()), np.zeros(()))
    with pytest.raises(TypeError):
        dp.accelerations(["a", "b"], [0, 0])
    with pytest.raises(TypeError):
        dp.accelerations([object(), 1], [0, 0])
    with pytest.raises(ValueError, match=r"\(5, 2\)"):
        dp.accelerations(np.zeros((5, 2)), np.zeros((5, 2)), out=np.zeros((5, 3)))
    with pytest.raises(TypeError):
        dp.accelerations(np.zeros((5, 2)), np.zeros((5, 2)), out=np.zeros((5, 2), dtype=np.float32))
    with pytest.raises(ValueError, match="C-contiguous"):
        dp.accelerations(np.zeros((5, 2)), np.zeros((5, 2)), out=np.zeros((2, 5)).T)
    q = np.zeros((5, 2))
    with pytest.raises(ValueError, match="share memory"):
        dp.accelerations(q, np.zeros((5, 2)), out=q)
    ro = np.zeros((5, 2))
    ro.flags.writeable = False
    with pytest.raises(ValueError, match="read-only"):
        dp.accelerations(q, q, out=ro)
    with pytest.raises(ValueError, match="no parameter or input 'k'"):
        dp.energy([0, 0], [0, 0], k=1)
    with pytest.raises(ValueError, match="finite"):
        dp.energy([0, 0], [0, 0], g=float("nan"))
    with pytest.raises(ValueError, match="finite"):
        dp.energy([0, 0], [0, 0], t=float("inf"))
    with pytest.raises(ValueError):
        dp.simulate(t_end=-1)
    with pytest.raises(ValueError):
        dp.simulate(dt=0)
    with pytest.raises(ValueError):
        dp.simulate(every=0)
    with pytest.raises(ValueError, match="cvode|sweeps"):
        dp.simulate(integrator="cvode")
    with pytest.raises(ValueError, match="adaptive"):
        dp.simulate(integrator="rk4", rtol=1e-6)
    with pytest.raises(ValueError, match="not a coordinate"):
        dp.simulate(initial={"x": 1})
    with pytest.raises(ValueError):
        dp.linearize(at={"th3": 0})
    with pytest.raises(ValueError):
        dp.sweep()
    with pytest.raises(phynjo.SingularMassMatrix):
        dp.accelerations([0, 0], [0, 0], m1=0, m2=0)
    failed = dp.simulate(t_end=1, params={"m1": 0, "m2": 0}, integrator="rk4")
    assert failed.status == "failed" and "singular" in failed.reason.lower()
    assert np.isfinite(dp.accelerations(np.zeros((0, 2)), np.zeros((0, 2)))).all()
    assert dp.accelerations(np.zeros((0, 2)), np.zeros((0, 2))).shape == (0, 2)
    with pytest.raises(TypeError):
        phynjo.compile_string(b"model x")


PUSHED = """model pushed
coordinates x [m]
parameters m = 2 [kg]
input F = 0 [N]
lagrangian 1/2*m*x'^2
force x = F
"""


def test_inputs_sampled_in_time(phynjo):
    """Catches: a table of input values not seen at each stage's time (held per step, read at
    the step's start, or never), interpolated wrongly: a ramp F = c t pushes a free mass
    exactly to x = c t^3 / (6 m) under RK4 (its stages integrate a ramp exactly), and a
    constant table gives the bits of a constant parameter."""
    m = phynjo.compile_string(PUSHED, "pushed.lag", cache_dir=CACHE)
    c = 3.0
    r = m.simulate(t_end=2, dt=0.01, integrator="rk4", inputs={"F": ([0, 10], [0, 10 * c])})
    exact = c * r.t ** 3 / (6 * 2.0)
    assert np.max(np.abs(r.q[:, 0] - exact)) < 1e-13
    held = m.simulate(t_end=2, dt=0.01, integrator="rk4", inputs={"F": ([0, 1, 5], [1.5, 1.5, 1.5])})
    const = m.simulate(t_end=2, dt=0.01, integrator="rk4", params={"F": 1.5})
    assert g17(held.rows) == g17(const.rows)
    # a step in F at t = 1 (two samples a hair apart): x'' = 0 before, F/m after
    step = m.simulate(t_end=2, dt=0.001, integrator="dopri", inputs={"F": ([1, 1 + 1e-9], [0, 4])})
    assert abs(step.q[-1, 0] - 0.5 * 2.0 * 1.0 ** 2) < 1e-6
    cp = phynjo.compile(model_path("cart_pole_input.lag"), cache_dir=CACHE)
    with pytest.raises(ValueError, match="not an input"):
        cp.simulate(t_end=0.1, inputs={"M": ([0], [1])})
    with pytest.raises(ValueError, match="increase"):
        cp.simulate(t_end=0.1, inputs={"F": ([1, 0], [0, 1])})
    with pytest.raises(ValueError, match="one length"):
        cp.simulate(t_end=0.1, inputs={"F": ([0, 1], [0])})
    with pytest.raises(ValueError, match="finite"):
        cp.simulate(t_end=0.1, inputs={"F": ([0, 1], [0, float("nan")])})


def test_control_called_every_k_steps(phynjo):
    """Catches: a controller called at the wrong steps or with a stale state, its values not
    held (or not used) until the next call, its exceptions lost: the calls' times, a constant
    controller's bits against the parameter, and a sampled PD law against the damped oscillator
    it approximates."""
    m = phynjo.compile_string(PUSHED, "pushed.lag", cache_dir=CACHE)
    calls = []

    def log(t, q, qd):
        calls.append((t, q[0], qd[0]))
        return {"F": 1.5}
    r = m.simulate(t_end=0.1, dt=0.001, integrator="rk4", control=log, control_every=5, every=5)
    assert [round(t / 0.005) for t, _, _ in calls] == list(range(20)) and calls[0][0] == 0.0
    assert g17([x for _, x, _ in calls]) == g17(r.q[:-1, 0])  # the state at each call
    const = m.simulate(t_end=0.1, dt=0.001, integrator="rk4", params={"F": 1.5}, every=5)
    assert g17(r.rows) == g17(const.rows)
    # F = -k x - c x' sampled every step of 1 ms: the damped oscillator m x'' + c x' + k x = 0
    k, c, mass = 8.0, 0.4, 2.0
    pd = m.simulate(t_end=5, dt=0.001, integrator="rk4", initial={"x": 1.0},
                    control=lambda t, q, qd: {"F": -k * q[0] - c * qd[0]})
    w0, z = math.sqrt(k / mass), c / (2 * math.sqrt(k * mass))
    wd = w0 * math.sqrt(1 - z * z)
    x = np.exp(-z * w0 * pd.t) * (np.cos(wd * pd.t) + z * w0 / wd * np.sin(wd * pd.t))
    err = np.max(np.abs(pd.q[:, 0] - x))
    assert 1e-5 < err < 5e-3  # a zero-order hold of 1 ms: close, not exact

    class Stop(Exception):
        pass

    def fails(t, q, qd):
        if t > 0.05:
            raise Stop("at 0.05 s")
        return {"F": 0.0}
    with pytest.raises(Stop):
        m.simulate(t_end=0.1, dt=0.001, control=fails)
    with pytest.raises(ValueError, match="not an input"):
        m.simulate(t_end=0.1, control=lambda t, q, qd: {"m": 1.0})
    with pytest.raises(TypeError, match="dict"):
        m.simulate(t_end=0.1, control=lambda t, q, qd: 1.0)
    with pytest.raises(ValueError, match="control returned F"):
        m.simulate(t_end=0.1, control=lambda t, q, qd: {"F": float("inf")})
    with pytest.raises(TypeError):
        m.simulate(t_end=0.1, control=3)


DROPPED = """model dropped
coordinates y [m]
parameters m = 1 [kg], g = 9.81 [m/s^2]
input u = 0 [m]
lagrangian 1/2*m*y'^2 - m*g*y
shape ball: sphere 1/20 [m] at (u, y, 0 [m])
event floor: y < 0 [m] -> stop
initial y = 1 [m]
"""


def test_a_results_page_is_the_simulators_page_of_that_run(phynjo, tmp_path):
    """Catches: a result's animation that is not its run (integrated again with other settings,
    frames taken at other states, the end or the stop reason or the events left out) or that
    draws the shapes with the inputs' defaults instead of the values they had: for a plain run
    and for one stopped by an event, Result.html() is byte for byte the simulator's --html page
    of the same run; a run whose controller (or input table) held u = 0.3 draws what a run with
    the parameter u = 0.3 draws."""
    dp = phynjo.compile(model_path("double_pendulum.lag"), cache_dir=CACHE)
    r = dp.simulate(t_end=1, dt=1e-3, integrator="rk4", params={"m2": 2}, initial={"th1": 0.5})
    cli = tmp_path / "cli.html"
    dp.run("--t-end", "1", "--dt", "0.001", "--integrator", "rk4", "--param", "m2=2", "--init", "th1=0.5",
           "--html", cli, "--output", tmp_path / "cli.csv")
    assert r.html() == cli.read_text(encoding="utf-8")
    assert r.html(tmp_path / "ours.html") == os.fspath(tmp_path / "ours.html")
    assert (tmp_path / "ours.html").read_text(encoding="utf-8") == cli.read_text(encoding="utf-8")

    m = phynjo.compile_string(DROPPED, "dropped.lag", cache_dir=CACHE)
    fell = m.simulate(t_end=2, dt=1e-3, integrator="rk4")
    assert fell.status == "stopped"
    cli = tmp_path / "dropped.html"
    m.run("--t-end", "2", "--dt", "0.001", "--integrator", "rk4", "--html", cli, "--output", tmp_path / "d.csv")
    page = fell.html()
    assert page == cli.read_text(encoding="utf-8") and "stopped by the event floor" in page

    held = m.simulate(t_end=0.3, dt=1e-3, integrator="rk4", params={"u": 0.3}).html()
    controlled = m.simulate(t_end=0.3, dt=1e-3, integrator="rk4", control=lambda t, q, qd: {"u": 0.3}).html()
    tabled = m.simulate(t_end=0.3, dt=1e-3, integrator="rk4", inputs={"u": ([0, 1], [0.3, 0.3])}).html()
    default = m.simulate(t_end=0.3, dt=1e-3, integrator="rk4").html()
    assert controlled == held and tabled == held and default != held
    with pytest.raises(ValueError, match="fps"):
        fell.html(fps=0)


def test_an_archived_run_killed_resumes_to_the_same_bits(phynjo, tmp_path):
    """Catches: simulate(archive=) not the same run as simulate(); a run killed with SIGKILL
    (in another interpreter) that resume() does not continue to the bits of the run never
    stopped (its rows, its events, its status); at(T) not the run's state at T; an archive
    of another parameter continued; archive= taken with a controller it cannot hold."""
    ball = phynjo.compile(model_path("bouncing_ball.lag"), cache_dir=CACHE)
    options = dict(t_end=3.5, dt=1e-5, integrator="rk4", every=50)  # (before its Zeno point, 4.06 s)
    plain = ball.simulate(**options)
    kept = ball.simulate(archive=tmp_path / "whole.par", **options)
    assert g17(kept.rows) == g17(plain.rows) and kept.status == plain.status == "finished"
    assert [(e.time, e.name) for e in kept.events] == [(e.time, e.name) for e in plain.events] and len(plain.events) > 5
    assert kept.first_event == plain.first_event
    assert abs(kept.max_energy_error - plain.max_energy_error) <= 1e-12
    # killed in another interpreter part way (a snapshot every 20,000 steps: 17 in the run),
    # when its rows pass a third of their length
    child = subprocess.Popen([sys.executable, "-c", (
        "import sys, phynjo; m = phynjo.compile(sys.argv[1], cache_dir=sys.argv[2] or None); "
        "m.simulate(t_end=3.5, dt=1e-5, integrator='rk4', every=50, archive=sys.argv[3], archive_every=20000)"),
        model_path("bouncing_ball.lag"), CACHE or "", str(tmp_path / "killed.par")], env=os.environ.copy())
    rows = tmp_path / "killed.par.csv"
    deadline = 600
    while child.poll() is None and (not rows.exists() or rows.stat().st_size < 200000) and deadline > 0:
        subprocess.run(["sleep", "0.01"])
        deadline -= 1
    child.kill()
    assert child.wait() == -9, "the run ended before it was killed: the test killed nothing"
    resumed = ball.resume(tmp_path / "killed.par", archive_every=20000, **options)
    assert g17(resumed.rows) == g17(plain.rows)
    assert [(e.time, e.name, g17(e.q)) for e in resumed.events] == [(e.time, e.name, g17(e.q)) for e in plain.events]
    # the state at T, from the snapshot before it
    for T in (0.73, 2.1, 3.49):
        s = ball.at(tmp_path / "killed.par", T, dt=1e-5, integrator="rk4", every=50)
        to = ball.simulate(t_end=T, dt=1e-5, integrator="rk4", every=50)
        assert g17([s.t, *s.q, *s.qd, s.energy]) == g17(to.rows[-1][:4]), T
    with pytest.raises(phynjo.RunError, match="param.e") as err:
        ball.resume(tmp_path / "killed.par", archive_every=20000, params={"e": 0.5}, **options)
    assert err.value.status == 1
    with pytest.raises(ValueError, match="control"):
        ball.simulate(archive=tmp_path / "c.par", control=lambda t, q, qd: {}, **options)


def test_quick_kernel_then_the_optimized_one(phynjo, tmp_path):
    """Catches: a quick kernel whose numbers are not the optimized kernel's (another
    arithmetic at -O0), a model that never moves to the optimized kernel once it is built, a
    sweep run on the quick kernel while the optimized one builds, the next compile rebuilding."""
    text = open(model_path("double_pendulum.lag")).read()
    cache = tmp_path / "cache"
    m = phynjo.compile_string(text, "double_pendulum.lag", cache_dir=cache)
    assert m._k.quick and not m.cache_hit and m.compile_seconds > 0  # built now: the quick kernel
    assert m._k.path.endswith(".quick.so")
    full = phynjo.compile_string(text, "double_pendulum.lag", cache_dir=tmp_path / "other", quick=False)
    assert not full.quick and full.kernel_path.endswith(".so") and not full.kernel_path.endswith(".quick.so")
    rng = np.random.default_rng(5)
    q, qd = rng.uniform(-3, 3, (200, 2)), rng.uniform(-3, 3, (200, 2))
    a = m.accelerations(q, qd)
    b = full.accelerations(q, qd)
    assert a.tobytes() == b.tobytes()
    r1 = m.simulate(t_end=3, dt=0.01, integrator="dopri", rtol=1e-9, atol=1e-9)
    r2 = full.simulate(t_end=3, dt=0.01, integrator="dopri", rtol=1e-9, atol=1e-9)
    assert r1.q.tobytes() == r2.q.tobytes() and r1.energy.tobytes() == r2.energy.tobytes()
    # a sweep waits for the optimized kernel, then runs on it: the same rows
    grid = {"th1": (-1, 1, 4), "th2": (-1, 1, 4)}
    s1 = m.sweep(grid=grid, t_end=1, dt=1e-2, threads=1)
    assert not m.quick and m.kernel_path == m._k.path and not m.kernel_path.endswith(".quick.so")
    s2 = full.sweep(grid=grid, t_end=1, dt=1e-2, threads=1)
    assert s1.tobytes() == s2.tobytes()
    # the next compile finds the optimized kernel
    again = phynjo.compile_string(text, "double_pendulum.lag", cache_dir=cache)
    assert again.cache_hit and not again._k.quick and again.kernel_path == m.kernel_path
