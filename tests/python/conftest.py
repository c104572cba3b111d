"""The Python package's tests (tests/CMakeLists.txt runs each test function as one ctest entry,
with PYTHONPATH at the build tree's package and these variables):
PHYNJO_SOURCE (the source tree), PHYNJO_EXAMPLES (the CMake-built simulators),
PHYNJO_TEST_CACHE (one kernel cache the entries share: each model compiles once per build)."""
import os
import subprocess
import sys

import pytest

SOURCE = os.environ.get("PHYNJO_SOURCE", os.path.join(os.path.dirname(__file__), "..", ".."))
EXAMPLES = os.environ.get("PHYNJO_EXAMPLES", "")
MODELS = os.path.join(SOURCE, "examples", "models")
TEST_MODELS = os.path.join(SOURCE, "tests", "codegen", "models")
CACHE = os.environ.get("PHYNJO_TEST_CACHE") or None


def model_path(name):
    for d in (MODELS, TEST_MODELS):
        p = os.path.join(d, name)
        if os.path.exists(p):
            return p
    raise FileNotFoundError(name)


@pytest.fixture(scope="session")
def phynjo():
    import phynjo as p
    return p


@pytest.fixture(scope="session")
def compile_model(phynjo):
    """phynjo.compile on the shared test cache."""
    return lambda name, **kw: phynjo.compile(model_path(name), cache_dir=kw.pop("cache_dir", CACHE), **kw)


def simulator(name):
    """A CMake-built simulator of the examples (phynjo_add_model(... MAIN))."""
    p = os.path.join(EXAMPLES, name)
    assert os.access(p, os.X_OK), f"no simulator {p} (PHYNJO_EXAMPLES)"
    return p


def run_simulator(name, *args):
    r = subprocess.run([simulator(name), *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r.stdout


def python():
    return sys.executable
