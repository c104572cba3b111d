"""phynjo from Python: a Lagrangian model (.lag, docs/language.md) compiled into a kernel, its
functions over NumPy arrays, runs, sweeps, linearizations and its equations (docs/python.md).

    import phynjo
    m = phynjo.compile("examples/models/double_pendulum.lag")
    r = m.simulate(t_end=10, dt=1e-3, integrator="dopri", rtol=1e-9)
    r.q[-1], r.max_energy_error

A model compiles once: its kernel is kept in a cache ($PHYNJO_CACHE_DIR, else
$XDG_CACHE_HOME/phynjo, else ~/.cache/phynjo) and found there the next time, in any process.
"""
import collections
import csv
import html as _html
import math
import os
import re
import sys
import tempfile

import numpy as np

from . import _phynjo
from ._errors import (BuildError, KernelError, ModelError, NonFiniteResult, PhynjoError, RunError,
                      SingularConstraints, SingularMassMatrix)

__version__ = _phynjo.__version__
__all__ = ["compile", "compile_string", "integrators", "Model", "Result", "Linearization", "Parameter",
           "Constraint", "Event", "EventRecord", "State", "PhynjoError", "ModelError", "BuildError", "KernelError",
           "SingularMassMatrix", "SingularConstraints", "NonFiniteResult", "RunError", "__version__"]

Parameter = collections.namedtuple("Parameter", "name default unit derived")
Parameter.__doc__ = ("A parameter or input: its name, the file's value (SI), its unit ('' when none), and "
                     "whether the file defines it from other parameters (it follows them until set).")
Constraint = collections.namedtuple("Constraint", "name holonomic")
Event = collections.namedtuple("Event", "name direction stops")
Event.__doc__ = "An event of the model: direction -1 falling, +1 rising; stops: it ends the run."
EventRecord = collections.namedtuple("EventRecord", "time name q qd")
#: The state of a run at one time (Model.at): t (s), q, qd (arrays of dof), energy (J).
State = collections.namedtuple("State", "t q qd energy")
EventRecord.__doc__ = "An event that fired: when (s), which, and the state just after its actions."
Integrator = collections.namedtuple("Integrator", "name order symplectic adaptive sweeps help")


# Long jobs (sweeps, command-line runs) wait this long (s) for a quick model's optimized kernel.
_SWEEP_WAIT = 300.0


def _cache_dir(cache_dir):
    return "" if cache_dir is None else os.fspath(cache_dir)


def compile(path, cache_dir=None, verbose=False, quick=True):
    """The model in the file `path` (.lag), compiled into a kernel unless the cache holds it.

    With `quick` (the default), a model whose optimized kernel is not in the cache gets a
    quick one first (built at -O0, in about two thirds of the compiler time; its code runs a
    few times slower) while the optimized kernel builds in the background. The two give the
    same bits; the model switches to the optimized kernel as soon as it is built, and sweep()
    and run() wait for it. quick=False builds the optimized kernel at once.

    Raises ModelError (the model's diagnostics, with file, line and column), BuildError (no
    C++ compiler, or it failed), OSError (the file cannot be read)."""
    path = os.fspath(path)
    if not os.path.isfile(path):
        raise FileNotFoundError(f"no model file '{path}'")
    with open(path, encoding="utf-8") as f:
        text = f.read()
    return Model(_phynjo.compile_string(text, path, _cache_dir(cache_dir), bool(verbose), bool(quick)), text, path)


def compile_string(text, name="<string>", cache_dir=None, verbose=False, quick=True):
    """The model in `text` (the .lag language), its diagnostics naming `name` (see compile)."""
    if not isinstance(text, str):
        raise TypeError("compile_string takes the model's text as a str")
    return Model(_phynjo.compile_string(text, name, _cache_dir(cache_dir), bool(verbose), bool(quick)), text, name)


def integrators():
    """Every integrator of the runtime (name, order, symplectic, adaptive, runs in sweeps, help),
    the default of the command line first."""
    return [Integrator(*e) for e in _phynjo.integrators()]


def _as_array(a, name):
    try:
        return np.ascontiguousarray(a, dtype=np.float64)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be an array of numbers: {e}") from None


class Linearization(collections.namedtuple("Linearization", "A B eigenvalues states inputs")):
    """y' = A y + B u about a state, y = (q, q'): A = dy'/dy (2n x 2n), B = dy'/du (2n x inputs),
    the eigenvalues of A; `states` names y's entries (th, th'), `inputs` u's."""

    @property
    def stable(self):
        """True when every eigenvalue of A has a negative real part."""
        return bool(np.all(self.eigenvalues.real < 0))


class Model:
    """A compiled model (phynjo.compile). Every function takes q and qd as arrays of shape
    (..., dof) — one state or many, batched over the leading axes — a time t (s), the
    parameters by name as keyword arguments (the file's values otherwise), and optionally
    `out`, a C-contiguous float64 array of the result's shape to write into."""

    def __init__(self, kernel, text, source):
        self._k = kernel
        self._text = text
        self.source = source
        self.name = kernel.name
        self.coordinates = tuple(kernel.coordinates)
        self.dof = kernel.dof
        params = [Parameter(n, d, u, derived) for (n, d, u, is_input, derived) in kernel.parameters if not is_input]
        inputs = [Parameter(n, d, u, derived) for (n, d, u, is_input, derived) in kernel.parameters if is_input]
        self.parameters = {p.name: p for p in params}
        self.inputs = {p.name: p for p in inputs}
        self.constraints = tuple(Constraint(*c) for c in kernel.constraints)
        self.events = tuple(Event(*e) for e in kernel.events)
        self.shapes = tuple(name for name, _ in kernel.shapes)

    # --- what the kernel is --------------------------------------------------------------
    def _kernel(self, wait=0.0):
        """The kernel to call: the optimized one as soon as its background build is done (the
        quick kernel's bits, faster), waiting for it up to `wait` s."""
        if self._k.quick:
            k = self._k.optimized(float(wait))
            if k is not None:
                self._k = k
        return self._k

    @property
    def quick(self):
        """True while the model runs on its quick kernel (compile's `quick`)."""
        return self._kernel().quick

    @property
    def kernel_path(self):
        """The shared object in the cache (the quick kernel's until the optimized one is built)."""
        return self._kernel().path

    @property
    def cache_hit(self):
        """True when compile found the kernel in the cache (no parse, no compiler)."""
        return self._k.cache_hit

    @property
    def compile_seconds(self):
        """The C++ compiler's wall time, s (0 on a cache hit)."""
        return self._k.compile_seconds

    def __repr__(self):
        return (f"<phynjo.Model {self.name}: coordinates {', '.join(self.coordinates)}; "
                f"parameters {', '.join(self.parameters) or '(none)'}>")

    # --- functions over arrays -----------------------------------------------------------
    def _params(self, params):
        for k, v in params.items():
            if k not in self.parameters and k not in self.inputs:
                raise ValueError(f"{self.name} has no parameter or input '{k}' (parameters: "
                                 f"{', '.join(self.parameters) or '(none)'}; inputs: {', '.join(self.inputs) or '(none)'})")
            try:
                v = float(v)
            except (TypeError, ValueError):
                raise TypeError(f"parameter {k} must be a number, not {v!r}") from None
            if not np.isfinite(v):
                raise ValueError(f"parameter {k} must be finite, not {v}")
        return {k: float(v) for k, v in params.items()}

    def _eval(self, fn, q, qd, t, out, params):
        q = _as_array(q, "q")
        qd = np.zeros_like(q) if qd is None else _as_array(qd, "qd")
        return self._kernel().evaluate(fn, q, qd, float(t), self._params(params), out)

    def accelerations(self, q, qd, t=0.0, out=None, **params):
        """q'' (..., dof): of M q'' = f, or with the constraints' multipliers eliminated."""
        return self._eval(_phynjo.Fn.accelerations, q, qd, t, out, params)

    def mass_matrix(self, q, qd=None, t=0.0, out=None, **params):
        """M (..., dof, dof), kg (m^2 for angles)."""
        return self._eval(_phynjo.Fn.mass_matrix, q, qd, t, out, params)

    def forcing(self, q, qd, t=0.0, out=None, **params):
        """f (..., dof) of M q'' = f."""
        return self._eval(_phynjo.Fn.forcing, q, qd, t, out, params)

    def energy(self, q, qd, t=0.0, out=None, **params):
        """E = sum(p q') - L (...), J."""
        return self._eval(_phynjo.Fn.energy, q, qd, t, out, params)

    def momenta(self, q, qd, t=0.0, out=None, **params):
        """p = dL/dq' (..., dof)."""
        return self._eval(_phynjo.Fn.momenta, q, qd, t, out, params)

    def generalized_forces(self, q, qd, t=0.0, out=None, **params):
        """Q (..., dof): the non-conservative forces of the model's `force` lines."""
        return self._eval(_phynjo.Fn.generalized_forces, q, qd, t, out, params)

    def rhs_jacobian(self, q, qd, t=0.0, out=None, **params):
        """dy'/dy (..., 2 dof, 2 dof) of y = (q, q'), exact."""
        return self._eval(_phynjo.Fn.rhs_jacobian, q, qd, t, out, params)

    def input_jacobian(self, q, qd, t=0.0, out=None, **params):
        """dy'/du (..., 2 dof, inputs), exact."""
        return self._eval(_phynjo.Fn.input_jacobian, q, qd, t, out, params)

    def constraint_residuals(self, q, qd, t=0.0, out=None, **params):
        """The constraints' residuals (..., constraints): 0 on them."""
        return self._eval(_phynjo.Fn.constraint_residuals, q, qd, t, out, params)

    def parameter(self, name, **params):
        """The value of a parameter or input (a derived one from the others given)."""
        self._params({name: 0.0})
        return self._kernel().parameter(self._params(params), name)

    def initial_state(self, **params):
        """(q, q') of the file's `initial` line (0 where it says nothing)."""
        return self._kernel().initial_state(self._params(params))

    def _state(self, at, what):
        """(q, q') from a dict of coordinate names and NAME' velocities."""
        q = np.zeros(self.dof)
        qd = np.zeros(self.dof)
        for k, v in (at or {}).items():
            name, velocity = (k[:-1], True) if k.endswith("'") else (k, False)
            if name not in self.coordinates:
                raise ValueError(f"{what}: '{k}' is not a coordinate (coordinates: {', '.join(self.coordinates)}; "
                                 f"a velocity is NAME')")
            (qd if velocity else q)[self.coordinates.index(name)] = float(v)
        return q, qd

    def linearize(self, at=None, t=0.0, **params):
        """The linearization about the state `at` ({"th": 0, "th'": 0, ...}; a coordinate or
        velocity not given is 0), the inputs at their values in `params`: A, B and the
        eigenvalues of A, exact Jacobians (no difference quotients)."""
        q, qd = self._state(at, "linearize")
        A = self.rhs_jacobian(q, qd, t, **params)
        B = self.input_jacobian(q, qd, t, **params)
        states = self.coordinates + tuple(c + "'" for c in self.coordinates)
        return Linearization(A, B, np.linalg.eigvals(A), states, tuple(self.inputs))

    # --- runs ----------------------------------------------------------------------------
    def _initial_pairs(self, initial):
        q0, v0 = [], []
        for k, v in (initial or {}).items():
            name, velocity = (k[:-1], True) if k.endswith("'") else (k, False)
            if name not in self.coordinates:
                raise ValueError(f"initial: '{k}' is not a coordinate (coordinates: {', '.join(self.coordinates)}; "
                                 f"a velocity is NAME')")
            v = float(v)
            if not np.isfinite(v):
                raise ValueError(f"initial: {k} must be finite, not {v}")
            (v0 if velocity else q0).append((self.coordinates.index(name), v))
        return q0, v0

    def simulate(self, t_end=10.0, dt=1e-3, integrator="midpoint", params=None, initial=None, every=1,
                 rtol=None, atol=None, inputs=None, control=None, control_every=1, archive=None, archive_every=None):
        """One run from the model's initial state (`initial` overrides values: {"th": 0.1,
        "th'": 0}) to t_end (s), steps of dt (s; Dormand-Prince's first trial step and its
        output spacing), with the model's events. The integrators are those sweeps run:
        rk4, dopri (rtol, atol), midpoint, rattle. The run is the simulator's: the same bits
        as `phynjo-run MODEL --t-end ... --output` (every `every`-th step, the first and the
        last). A run that fails (a singular matrix, a NaN) is a Result with status 'failed'
        and the reason, not an exception.

        Inputs varying in time (the model's `input` names):
        `inputs={"F": (times, values)}` — a table sampled in time, piecewise linear between
        the samples and held beyond them, seen by the model at every time it is evaluated
        at (each stage of a step);
        `control=f` — f(t, q, qd) returns {input: value}, called at t = 0 and every
        `control_every` steps with the state there; the values hold until the next call
        (zero-order hold: a sampled controller). What f raises is raised by simulate.

        `archive="run.par"` keeps the run in a simulation archive (docs/archive.md): a
        snapshot a second of wall time (`archive_every`: K steps, or "Xs" seconds), the rows
        in "run.par.csv" and the events in "run.par.events.csv" beside it. A run killed at
        any moment continues with `resume("run.par", the same options)`, to the same bits;
        `at("run.par", T, the same options)` is the state at any time T. Not with inputs= or
        control= (the archive holds neither the tables nor the controller)."""
        p = self._params(params or {})
        if archive is not None:
            if inputs or control is not None:
                raise ValueError("simulate: archive= takes a run without inputs= or control= (the archive holds "
                                 "neither their tables nor the controller)")
            return self._archived("--archive", archive, archive_every, t_end, dt, integrator, params, initial, every,
                                  rtol, atol)
        q0, v0 = self._initial_pairs(initial)
        table = []
        for name, sampled in (inputs or {}).items():
            if name not in self.inputs:
                raise ValueError(f"inputs: '{name}' is not an input of {self.name} "
                                 f"(inputs: {', '.join(self.inputs) or 'none'})")
            try:
                times, values = sampled
            except (TypeError, ValueError):
                raise ValueError(f"inputs['{name}'] must be (times, values)") from None
            times = np.ravel(_as_array(times, f"inputs['{name}'] times"))
            values = np.ravel(_as_array(values, f"inputs['{name}'] values"))
            table.append((name, times.tolist(), values.tolist()))
        if control is not None and not callable(control):
            raise TypeError("control must be callable: control(t, q, qd) -> {input: value}")
        d = self._kernel().simulate(float(t_end), float(dt), str(integrator), p, q0, v0, int(every), rtol, atol,
                             table, control, int(control_every))
        options = dict(t_end=float(t_end), dt=float(dt), integrator=str(integrator), params=p,
                       initial=dict(initial or {}), rtol=rtol, atol=atol, inputs=table)
        return Result(self, d, options)

    def resume(self, archive, t_end=10.0, dt=1e-3, integrator="midpoint", params=None, initial=None, every=1,
               rtol=None, atol=None, archive_every=None):
        """Continues the run `simulate(archive=...)` kept in `archive`, killed or finished (a
        later t_end runs it further), from its last snapshot, with the same options: the
        Result is the run's that was never stopped, bit for bit (its rows file cut back to
        the snapshot and continued). Raises RunError (status 1) for an archive of another
        model, parameter or option, naming it."""
        return self._archived("--resume", archive, archive_every, t_end, dt, integrator, params, initial, every,
                              rtol, atol)

    def at(self, archive, t, dt=1e-3, integrator="midpoint", params=None, initial=None, every=1, rtol=None,
           atol=None):
        """The state at time `t` (s) of the run `simulate(archive=...)` kept in `archive`,
        given with the same options: State(t, q, qd, energy), the last row a run to t_end = t
        ends with, bit for bit, integrated from the latest snapshot at or before t."""
        archive = os.fspath(archive)
        args = self._run_options(t, dt, integrator, params, initial, rtol, atol)
        args += ["--every", str(int(every)), "--archive", archive, "--at", repr(float(t)), "--output", "/dev/stdout"]
        status, out, err = _captured(lambda: self._kernel(_SWEEP_WAIT).run("phynjo-run " + self.source, args))
        if status != 0:
            raise RunError(status, err.strip() or f"at: the run exited with status {status}")
        row = np.array([float(v) for v in out.strip().splitlines()[-1].split(",")])
        n = self.dof
        return State(row[0], row[1:1 + n], row[1 + n:1 + 2 * n], row[1 + 2 * n])

    def _archived(self, how, archive, archive_every, t_end, dt, integrator, params, initial, every, rtol, atol):
        """simulate(archive=) and resume(): the simulator's driver with --archive or --resume
        (the same run, bit for bit, as simulate's), read back into a Result."""
        archive = os.fspath(archive)
        rows_path, events_path = archive + ".csv", archive + ".events.csv"
        args = self._run_options(t_end, dt, integrator, params, initial, rtol, atol)
        args += ["--every", str(int(every)), "--output", rows_path, how, archive]
        if self.events:
            args += ["--events", events_path]
        if archive_every is not None:
            args += ["--archive-every", str(archive_every)]
        status, out, err = _captured(lambda: self._kernel(_SWEEP_WAIT).run("phynjo-run " + self.source, args))
        failed = re.search(r"simulation stopped at t = \S+: (.*)", err)
        if status != 0 and not (status == 1 and failed and os.path.exists(rows_path)):
            raise RunError(status, err.strip() or f"the run exited with status {status}")
        rows = np.loadtxt(rows_path, delimiter=",", skiprows=1, ndmin=2)
        events = []
        if self.events:
            with open(events_path, encoding="utf-8") as f:
                for line in f.read().splitlines()[1:]:
                    cells = line.split(",")
                    values = np.array([float(v) for v in cells[2:]])
                    events.append((float(cells[0]), cells[1], values[:self.dof], values[self.dof:]))
        stopped = re.search(r"the run stopped at t = \S+: event '([^']*)'", err)
        e = rows[:, 1 + 2 * self.dof]
        d = {
            "rows": rows,
            "status": "failed" if failed else "stopped" if stopped else "finished",
            "reason": failed.group(1) if failed else f"event {stopped.group(1)}" if stopped else "",
            "t": rows[-1, 0],
            "first_event": [next((t for t, name, _, _ in events if name == ev.name), math.nan) for ev in self.events],
            "max_energy_error": float(np.max(np.abs(e - e[0])) / max(1.0, abs(e[0]))),
            "events": events,
            "control_log": [],
        }
        options = dict(t_end=float(t_end), dt=float(dt), integrator=str(integrator), params=self._params(params or {}),
                       initial=dict(initial or {}), rtol=rtol, atol=atol, inputs=[])
        return Result(self, d, options)

    def run(self, *args):
        """The simulator's command line on this model (phynjo-run MODEL ARGS...: --help lists
        the options): what it printed on standard output, as a str. Raises RunError (its exit
        status and what it printed on standard error) when it does not exit 0; warnings it
        prints on success go to sys.stderr."""
        words = [os.fspath(a) if isinstance(a, os.PathLike) else str(a) for a in args]
        status, out, err = _captured(lambda: self._kernel(_SWEEP_WAIT).run("phynjo-run " + self.source, words))
        if status != 0:
            raise RunError(status, err.strip() or f"the run exited with status {status}")
        if err:
            sys.stderr.write(err)
        return out

    def _run_options(self, t_end, dt, integrator, params, initial, rtol=None, atol=None):
        args = ["--t-end", repr(float(t_end)), "--dt", repr(float(dt)), "--integrator", str(integrator)]
        for k, v in self._params(params or {}).items():
            args += ["--param", f"{k}={v!r}"]
        self._initial_pairs(initial)  # checks the names
        for k, v in (initial or {}).items():
            args += ["--init", f"{k}={float(v)!r}"]
        if rtol is not None:
            args += ["--rtol", repr(float(rtol))]
        if atol is not None:
            args += ["--atol", repr(float(atol))]
        return args

    def sweep(self, grid=None, uniform=None, samples=None, seed=0, t_end=10.0, dt=1e-3, integrator="rk4",
              params=None, initial=None, threads=1, summary=None, lanes=True):
        """Many runs, one row each (the simulator's --summary): `grid` {name: (lo, hi, n)}, the
        runs its points (the first axis slowest); `uniform` {name: (lo, hi)} with `samples`
        draws from `seed`; a name is a parameter or input, a coordinate (its initial value) or
        NAME' (its initial velocity). Returns a NumPy structured array: run, the swept values,
        status, t, end_q..., end_q'..., each event's first time (NaN: never),
        max_energy_error, reason. `summary`: a CSV file kept (a sweep interrupted goes on from
        its last complete row when run again with the same options). The same rows for any
        `threads`."""
        if not grid and not uniform:
            raise ValueError("sweep: give grid={name: (lo, hi, n)} and/or uniform={name: (lo, hi)}")
        args = self._run_options(t_end, dt, integrator, params, initial)
        for k, v in (grid or {}).items():
            try:
                lo, hi, n = v
            except (TypeError, ValueError):
                raise ValueError(f"sweep: grid[{k!r}] must be (lo, hi, n)") from None
            args += ["--grid", f"{k}={float(lo)!r}:{float(hi)!r}:{int(n)}"]
        for k, v in (uniform or {}).items():
            try:
                lo, hi = v
            except (TypeError, ValueError):
                raise ValueError(f"sweep: uniform[{k!r}] must be (lo, hi)") from None
            args += ["--uniform", f"{k}={float(lo)!r}:{float(hi)!r}"]
        if uniform:
            if samples is None:
                raise ValueError("sweep: uniform needs samples=K")
            args += ["--samples", str(int(samples)), "--seed", str(int(seed))]
        args += ["--threads", str(int(threads))]
        if not lanes:
            args.append("--no-lanes")
        with tempfile.TemporaryDirectory(prefix="phynjo-sweep-") as tmp:
            path = os.fspath(summary) if summary is not None else os.path.join(tmp, "summary.csv")
            self.run(*args, "--summary", path)
            return _read_summary(path)

    # --- equations -----------------------------------------------------------------------
    def latex(self):
        """A LaTeX document of the model: coordinates, parameters, L, M q'' = f, E."""
        return _phynjo.document(self._text, self.source, "latex")

    def _repr_latex_(self):
        """Jupyter: the equations of motion, M and f, as one aligned display."""
        doc = self.latex()
        body = doc.split(r"\subsection*{Equations of motion", 1)[-1]
        rows = re.findall(r"^\\\[ (.*) \\\]$", body, flags=re.M)
        if not rows:
            return None
        rows = [r.replace(" = ", " &= ", 1) for r in rows]
        return "$$\\begin{aligned}" + " \\\\ ".join(rows) + "\\end{aligned}$$"

    def equations(self):
        """(M, f) of M q'' = f as SymPy matrices, the coordinates as functions of t, the
        parameters as symbols: a bridge to SymPy for those who go on symbolically. Needs SymPy
        (Debian's python3-sympy)."""
        try:
            import sympy
        except ImportError:
            raise ImportError("Model.equations needs SymPy (apt-get install python3-sympy)") from None
        t = sympy.Symbol("t")
        names = {c: sympy.Function(c)(t) for c in self.coordinates}
        local = dict(names)
        for c in self.coordinates:
            local["_v_" + c] = sympy.Derivative(names[c], t)
        for p in list(self.parameters) + list(self.inputs):
            local[p] = sympy.Symbol(p)
        local.update(t=t, pi=sympy.pi, abs=sympy.Abs, sign=sympy.sign, atan2=sympy.atan2)
        n = self.dof
        M = sympy.zeros(n, n)
        f = sympy.zeros(n, 1)

        def parse(text):
            text = re.sub(r"([A-Za-z_][A-Za-z0-9_]*)'", r"_v_\1", text).replace("^", "**")
            return sympy.parse_expr(text, local_dict=local, evaluate=True)

        for line in _phynjo.document(self._text, self.source, "equations").splitlines():
            m = re.match(r"^M\((\d+),(\d+)\) = (.*)$", line)
            if m:
                M[int(m[1]) - 1, int(m[2]) - 1] = parse(m[3])
                continue
            m = re.match(r"^f\((\d+)\) = (.*)$", line)
            if m:
                f[int(m[1]) - 1] = parse(m[2])
        return M, f


class Result:
    """One run (Model.simulate): `t` (rows,), `q` and `qd` (rows, dof), `energy` (rows,);
    `status` ('finished', 'stopped' by an event, 'failed'), `reason`, `t_end` (where it
    ended), `first_event` {name: time or None}, `events` (EventRecord: time, name, q, qd),
    `max_energy_error` (max |E - E(0)| / max(1, |E(0)|)). `rows` is the whole table
    t, q..., q'..., E — the simulator's --output, bit for bit."""

    def __init__(self, model, d, options):
        self.model = model
        self.rows = d["rows"]
        n = model.dof
        self.t = self.rows[:, 0]
        self.q = self.rows[:, 1:1 + n]
        self.qd = self.rows[:, 1 + n:1 + 2 * n]
        self.energy = self.rows[:, 1 + 2 * n]
        self.status = d["status"]
        self.reason = d["reason"]
        self.t_end = d["t"]
        self.max_energy_error = d["max_energy_error"]
        self.first_event = {e.name: (None if np.isnan(v) else v) for e, v in zip(model.events, d["first_event"])}
        self.events = [EventRecord(time, name, np.array(q), np.array(qd)) for time, name, q, qd in d["events"]]
        self._options = options
        self._d = d

    def __repr__(self):
        why = f" ({self.reason})" if self.reason else ""
        return (f"<phynjo.Result {self.model.name}: {len(self.t)} rows to t = {self.t_end:g} s, {self.status}{why}; "
                f"{len(self.events)} events; max relative energy error {self.max_energy_error:.3g}>")

    def html(self, path=None, fps=None):
        """The run as a 3-D animation, one HTML page that plays offline (docs/viewer.md): this
        run's own rows drawn (nothing is integrated again; a run with every=k has a frame at
        most every k steps), the inputs at the values they had (inputs= tables, what control=
        set), its events marked. For a run with every=1 the page is the simulator's --html page
        of the same run, byte for byte. Written to `path` (returned), or returned as text when
        `path` is None."""
        o = self._options
        title = f"{self.model.name} ({o['integrator']}, dt = {o['dt']:g} s)"
        events = [(t, name) for t, name, _, _ in self.events]
        page = self.model._k.html(o["params"], self.rows, o["inputs"], self._d["control_log"],
                                  60.0 if fps is None else float(fps), title, events, self._stop_text())
        if path is None:
            return page
        out = os.fspath(path)
        with open(out, "w", encoding="utf-8") as f:
            f.write(page)
        return out

    def _stop_text(self):
        """Why the run ended early, in the simulator's words for its page ("" when it finished)."""
        if self.status == "stopped" and self.events:
            last = self.events[-1]
            return f"stopped by the event {last.name} at t = {last.time:.10g} s"
        if self.status == "failed":
            return f"the simulation failed at t = {self.t_end:.10g} s: {self.reason}"
        return ""

    def _repr_html_(self):
        """Jupyter: the animation in an iframe (its page is self-contained)."""
        return ('<iframe style="width:100%;height:560px;border:0" sandbox="allow-scripts" srcdoc="'
                + _html.escape(self.html(), quote=True) + '"></iframe>')

    def plot(self, ax=None):
        """q(t) and E(t) - E(0) with matplotlib (python3-matplotlib): the axes drawn on."""
        import matplotlib.pyplot as plt
        if ax is None:
            _, ax = plt.subplots(2, 1, sharex=True, figsize=(7, 5))
        axes = np.atleast_1d(ax)
        for i, c in enumerate(self.model.coordinates):
            axes[0].plot(self.t, self.q[:, i], label=c)
        axes[0].set_ylabel("q")
        axes[0].legend(loc="upper right")
        if len(axes) > 1:
            axes[1].plot(self.t, self.energy - self.energy[0])
            axes[1].set_ylabel("E - E(0) / J")
        axes[-1].set_xlabel("t / s")
        return axes


def _captured(call):
    """call() with the process's standard output and error (file descriptors 1 and 2: C++
    writes there, not to sys.stdout) captured: (its value, stdout text, stderr text)."""
    for s in (sys.stdout, sys.stderr):
        try:
            s.flush()
        except (AttributeError, ValueError):
            pass
    with tempfile.TemporaryFile() as out, tempfile.TemporaryFile() as err:
        saved = os.dup(1), os.dup(2)
        try:
            os.dup2(out.fileno(), 1)
            os.dup2(err.fileno(), 2)
            value = call()
        finally:
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            os.close(saved[0])
            os.close(saved[1])
        out.seek(0)
        err.seek(0)
        return value, out.read().decode("utf-8", "replace"), err.read().decode("utf-8", "replace")


def _read_summary(path):
    """A sweep's --summary CSV as a structured array (the # line skipped)."""
    with open(path, newline="", encoding="utf-8") as f:
        lines = [line for line in f if not line.startswith("#")]
    reader = csv.reader(lines)
    header = next(reader)
    rows = list(reader)
    text_columns = {"status", "reason"}
    dtype = []
    for h in header:
        if h == "run":
            dtype.append((h, np.int64))
        elif h in text_columns:
            width = max([len(r[header.index(h)]) for r in rows] + [1])
            dtype.append((h, f"U{width}"))
        else:
            dtype.append((h, np.float64))
    out = np.empty(len(rows), dtype=dtype)
    for i, r in enumerate(rows):
        out[i] = tuple(int(v) if h == "run" else v if h in text_columns else (float(v) if v != "" else np.nan)
                       for h, v in zip(header, r))
    return out
