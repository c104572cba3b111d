"""phynjo's exceptions (raised by the compiled module too: python/src/module.cpp)."""
import re

__all__ = ["PhynjoError", "ModelError", "BuildError", "KernelError", "SingularMassMatrix",
           "SingularConstraints", "NonFiniteResult", "RunError"]


class PhynjoError(RuntimeError):
    """Any error of phynjo's."""


_DIAGNOSTIC = re.compile(r"^(?P<file>.*?):(?P<line>\d+):(?P<column>\d+): error: (?P<message>.*)$")


class ModelError(PhynjoError, ValueError):
    """The model has errors. str() is every diagnostic, ``FILE:LINE:COL: error: ...`` with the
    line and a caret; ``file``, ``line``, ``column``, ``message`` and ``source_line`` (the line
    and its caret) are the first one's, ``diagnostics`` all of them as (file, line, column,
    message)."""

    def __init__(self, text):
        super().__init__(text)
        self.diagnostics = []
        lines = str(text).splitlines()
        first = None
        for i, line in enumerate(lines):
            m = _DIAGNOSTIC.match(line)
            if m:
                d = (m["file"], int(m["line"]), int(m["column"]), m["message"])
                self.diagnostics.append(d)
                if first is None:
                    first = i
        if first is not None:
            self.file, self.line, self.column, self.message = self.diagnostics[0]
            self.source_line = "\n".join(lines[first + 1:first + 3])
        else:
            self.file, self.line, self.column, self.message, self.source_line = None, None, None, str(text), ""


class BuildError(PhynjoError):
    """No C++ compiler, or it failed on a model's kernel: the message says what to install, or
    shows the compiler's output."""


class KernelError(PhynjoError):
    """A compiled kernel does not load (not a shared object, another ABI version)."""


class SingularMassMatrix(PhynjoError):
    """The mass matrix is singular at the state given."""


class SingularConstraints(PhynjoError):
    """The constraints' Jacobian lost rank at the state given."""


class NonFiniteResult(PhynjoError):
    """A model function gave a NaN or an infinity."""


class RunError(PhynjoError):
    """The simulator's command line (Model.run, Model.sweep) failed: ``status`` is its exit
    status (1 a failed run, 2 a usage error, 3 energy drift with --fail-on-drift), str() what
    it printed on standard error."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status
