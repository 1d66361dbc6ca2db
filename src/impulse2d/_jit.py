"""How the engine's kernels are compiled.

Every stage of the step is a plain Python function over numpy arrays and scalars,
compiled by numba. With ``NUMBA_DISABLE_JIT=1`` the very same functions run in CPython
and give bitwise the same results (a test runs a scene both ways): that is how the
engine stays "pure Python" while running at compiled speed.

The options, and why:

* ``cache=True``: compiled code is written next to the sources (``__pycache__``) and
  loaded on the next import instead of compiled again.
* ``nogil=True``: a kernel releases the GIL, so other Python threads keep running.
* no ``fastmath``: results must be bitwise repeatable, and the same alone, in a batch and
  on any number of threads. For the same reason kernels use ``math`` on scalars and
  write squares as ``x * x`` (CPython's ``x ** 2`` and ``math.hypot`` round differently
  from the compiled ones), and never divide by a number that can be zero.
"""

from __future__ import annotations

import contextlib
import hashlib
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numba

F = TypeVar("F", bound=Callable[..., Any])

JIT_DISABLED = bool(numba.config.DISABLE_JIT)
_PACKAGE = Path(__file__).parent


def kernel_sources_digest(package: Path) -> str:
    """SHA-256 of the modules under ``package`` that kernels are compiled from: those
    that define kernels, and ``state.py`` and ``settings.py`` whose constants they use."""
    digest = hashlib.sha256()
    for path in sorted(package.glob("*.py")):
        source = path.read_bytes()
        if b"from ._jit import" in source or path.name in ("state.py", "settings.py"):
            digest.update(path.name.encode() + source)
    return digest.hexdigest()


def clear_stale_cache(cache: str) -> None:
    """Drop compiled kernels built from other sources than these, in the directory numba
    caches this package's kernels in (``__pycache__``, or under ``NUMBA_CACHE_DIR``).

    numba checks a cached function against its own file only, but a kernel inlines the
    functions it calls from other modules: after an edit or an upgrade in place (``git
    pull`` on an editable install) a kernel could run the code it was compiled from. So
    the cache is stamped with a hash of the package's kernel modules (and of the
    constants they are compiled with), and emptied when the sources differ from it.
    ``pipeline`` calls this on import, before any kernel runs. Editing another module
    (the facades, the envs) keeps the cache."""
    stamp, directory = kernel_sources_digest(_PACKAGE), Path(cache)
    marker = directory / "kernels.sha256"
    with contextlib.suppress(OSError):
        if marker.exists() and marker.read_text() == stamp:
            return
        for cached in directory.glob("*.nb[ic]"):
            cached.unlink(missing_ok=True)
        directory.mkdir(parents=True, exist_ok=True)
        marker.write_text(stamp)


def kernel(function: F) -> F:
    """Compile a function that runs on one thread."""
    return numba.njit(
        cache=True,
        nogil=True,
    )(function)


def inline(function: F) -> F:
    """Compile a small helper of the hot loops, inlined into its callers by numba (so
    the arrays it is handed cost no reference counting per call)."""
    return numba.njit(cache=True, nogil=True, inline="always")(function)


def parallel_kernel(function: F) -> F:
    """Compile a function whose ``numba.prange`` loops run on the world's threads."""
    return numba.njit(cache=True, nogil=True, parallel=True)(function)
