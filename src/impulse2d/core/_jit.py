"""How the engine's kernels are compiled.

Every stage of the step is a plain Python function over numpy arrays and scalars,
compiled by numba. With ``NUMBA_DISABLE_JIT=1`` the very same functions run in CPython
and give bitwise the same results (a test runs a scene both ways): that is how the
engine stays "pure Python" while running at compiled speed.

The options, and why:

* ``cache=True``: compiled code is written next to the sources (``__pycache__``) and
  loaded on the next import instead of compiled again. Where that folder cannot be
  written (a read-only install: a system site-packages, an image, a shared cluster
  folder) and ``NUMBA_CACHE_DIR`` is not set, the kernels are cached in the user's cache
  folder instead, ``$XDG_CACHE_HOME/impulse2d/numba`` (``~/.cache/impulse2d/numba``
  without ``XDG_CACHE_HOME``); see ``choose_cache_dir``. ``python -m impulse2d.compile``
  fills the cache ahead of the first run.
* ``nogil=True``: a kernel releases the GIL, so other Python threads keep running.
* one signature per kernel: numba compiles a kernel again for every literal argument it
  is called with from another kernel (``f(x, 0)`` and ``f(x, k)`` are two compiles, and
  so are a defaulted argument left out and passed); ``kernel`` makes such calls share
  the compile for the plain types (``_one_signature``). A literal only lets numba fold a
  branch, which changes no result.
* ``inline`` for two kinds of function. The small helpers of the solver's and the
  contacts' inner loops (called per point, where a call and its reference counting
  cost ~20 % of a step). And the few levels above the stages, each called from one
  place (``advance_world``, ``step_world``, ``collide_and_wake``, ``substeps``,
  ``finish``; ``solve`` and ``relax``): numba links every kernel a kernel calls into its
  module and optimises and emits all of it again, so each such level compiled as a
  kernel of its own cost ~2 s of every first run (inlined, the first step compiles in
  27 s of CPU instead of 33, a first batched step in 27 instead of 41). Not the stages
  themselves: numba's inlining pass grows faster than the code it inlines, and with
  every single-call stage inlined the first step took 100 s. A function inlined at
  several call sites is compiled once per site.
* arrays borrowed, not owned, inside a call (``borrowed``): numba counts references to
  every array a kernel is handed, with an atomic increment at the kernel's entry and an
  atomic decrement at its exit, per array and per call; a step calls its stages a few
  dozen times, and in a small world those counts were nearly half the step (the pool
  break: 3.85 us a step, 2.11 with the step's arrays borrowed; threads stepping chunks
  of a batch also fight over the counters' cache lines). The entry point of a step
  (``pipeline.advance``) takes its arrays once and hands the stages borrowed views of
  them: the same memory without a reference count, which the caller's own reference
  keeps alive until the call returns.
* no ``fastmath``: results must be bitwise repeatable, and the same alone, in a batch and
  on any number of threads. For the same reason kernels use ``math`` on scalars and
  write squares as ``x * x`` (CPython's ``x ** 2`` and ``math.hypot`` round differently
  from the compiled ones), and never divide by a number that can be zero.
"""

from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any, TypeVar

import numba
from numba.core import cgutils, errors, types
from numba.extending import intrinsic
from numba.np.arrayobj import populate_array

from ._shipped import portable

F = TypeVar("F", bound=Callable[..., Any])

JIT_DISABLED = bool(numba.config.DISABLE_JIT)
_PACKAGE = Path(__file__).parent  # impulse2d/core: every kernel is defined in it


def _writable(folder: Path) -> bool:
    """Whether numba can write its cache files in ``folder`` (made if missing)."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        tempfile.TemporaryFile(dir=folder).close()
    except OSError:
        return False
    return True


def user_cache_dir() -> Path:
    """The user's cache folder for compiled kernels (XDG base directory spec)."""
    base = os.environ.get("XDG_CACHE_HOME", "").strip() or str(Path.home() / ".cache")
    return Path(base) / "impulse2d" / "numba"


def choose_cache_dir(package: Path = _PACKAGE) -> str | None:
    """Point numba's cache at the user's cache folder when the package's ``__pycache__``
    cannot be written and ``NUMBA_CACHE_DIR`` is not set; returns the folder chosen
    (None: numba's own choice stands).

    Runs when this module is imported, before any kernel is decorated (numba fixes a
    kernel's cache folder then). Setting ``numba.config.CACHE_DIR`` rather than the
    environment leaves child processes to decide for themselves, the same way."""
    if JIT_DISABLED or numba.config.CACHE_DIR or _writable(package / "__pycache__"):
        return None
    folder = user_cache_dir()
    if not _writable(folder):
        return None  # nowhere to write: numba compiles every run, as it would anyway
    numba.config.CACHE_DIR = str(folder)
    return str(folder)


CACHE_DIR = choose_cache_dir()


# Modules of the core that no kernel is compiled from: how the cache finds kernels.
_NOT_COMPILED = frozenset({"_shipped.py"})


def kernel_sources_digest(package: Path) -> str:
    """SHA-256 of the modules kernels are compiled from: every module of ``package`` (the
    core: the kernels, the state's and the step context's columns) but ``_NOT_COMPILED``,
    and the envelope's limits (``envelope.py`` beside it)."""
    digest = hashlib.sha256()
    modules = [path for path in sorted(package.glob("*.py")) if path.name not in _NOT_COMPILED]
    for path in [*modules, package.parent / "envelope.py"]:
        digest.update(path.name.encode() + path.read_bytes())
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


def _plain(argument: types.Type) -> types.Type:
    """The type a kernel is compiled for in place of ``argument``: a literal's own type
    (``int64`` for ``Literal[int](0)``), a left-out defaulted argument's default's type."""
    if isinstance(argument, types.Omitted):
        return types.unliteral(numba.typeof(argument.value))
    return types.unliteral(argument)


def _one_signature(dispatcher: Any) -> Any:
    """Make calls to ``dispatcher`` from other kernels compile it for plain types only.

    numba types a constant argument as a literal and compiles the callee once per
    literal; here the call asks for the plain types instead (numba casts the literal at
    the call). A kernel that only types with a literal (a tuple indexed by an argument)
    keeps numba's way. Python calls are typed from values, never literals: unchanged."""
    compiler = getattr(dispatcher, "_compiler", None)
    if not hasattr(compiler, "fold_argument_types"):
        # NUMBA_DISABLE_JIT (a plain function), or a numba whose internals moved: its
        # own typing stands (more compiles, the same results).
        return dispatcher
    specialised = dispatcher.get_call_template

    def get_call_template(args: tuple[Any, ...], kws: dict[str, Any]) -> Any:
        _, folded = dispatcher._compiler.fold_argument_types(args, kws)
        plain = tuple(_plain(argument) for argument in folded)
        if plain != tuple(folded):
            with contextlib.suppress(errors.TypingError):
                return specialised(plain, {})
        return specialised(args, kws)

    dispatcher.get_call_template = get_call_template
    return dispatcher


def kernel(function: F) -> F:
    """Compile a function that runs on one thread."""
    return _one_signature(portable(numba.njit(cache=True, nogil=True)(function)))


def inline(function: F) -> F:
    """Compile a function inlined into its callers by numba: a small helper of the hot
    loops (the arrays it is handed cost no reference counting per call), or a level of
    the step with one call site (see the module docstring). Each call site compiles it
    again."""
    return portable(numba.njit(cache=True, nogil=True, inline="always")(function))


@intrinsic
def _borrowed(typingctx: Any, array: types.Type) -> Any:
    """``array`` with a null meminfo and parent: a view numba does not count references
    to (its reference counting checks for null and returns)."""
    if not isinstance(array, types.Array):
        return None

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        view = context.make_array(array)(context, builder, value=args[0])
        view.meminfo = cgutils.get_null_value(view.meminfo.type)
        view.parent = cgutils.get_null_value(view.parent.type)
        return view._getvalue()

    return array(array), codegen


def _same_array(array: Any) -> Any:
    return array


# ``borrowed(array)``: the same array, not reference-counted (see the module docstring),
# for a kernel's caller that holds ``array`` for as long as the kernel runs. Without the
# compiler (NUMBA_DISABLE_JIT) the array itself: CPython counts its references anyway.
borrowed = _same_array if JIT_DISABLED else _borrowed


@intrinsic
def _cut(typingctx: Any, flat: types.Type, start: types.Type, rows: types.Type, cols: types.Type):
    """``flat[start : start + rows * cols]`` as a C-contiguous ``(rows, cols)`` array,
    borrowed (as ``borrowed``), without bounds checks: a slice and a ``reshape`` cost a
    call a few dozen nanoseconds each (numba normalises the slice and asks a C helper
    whether the reshape can be a view), and a call cuts its scratch row into a dozen
    arrays."""
    if not (isinstance(flat, types.Array) and flat.ndim == 1 and flat.layout == "C"):
        return None
    if not all(isinstance(n, types.Integer) for n in (start, rows, cols)):
        return None
    out = types.Array(flat.dtype, 2, "C")

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        source = context.make_array(flat)(context, builder, value=args[0])
        at, height, width = (
            context.cast(builder, value, kind, types.intp)
            for value, kind in zip(args[1:], signature.args[1:], strict=True)
        )
        size = context.get_abi_sizeof(context.get_data_type(flat.dtype))
        itemsize = context.get_constant(types.intp, size)
        view = context.make_array(out)(context, builder)
        populate_array(
            view, data=builder.gep(source.data, [at]), shape=[height, width],
            strides=[builder.mul(width, itemsize), itemsize], itemsize=itemsize, meminfo=None,
        )  # fmt: skip
        return view._getvalue()

    return out(flat, start, rows, cols), codegen


def _sliced(flat: Any, start: int, rows: int, cols: int) -> Any:
    return flat[start : start + rows * cols].reshape(rows, cols)


# ``cut(flat, start, rows, cols)``: a (rows, cols) view of a 1-D C-contiguous array from
# ``start`` on, borrowed; the caller makes sure it fits. Without the compiler, the
# slice and reshape it stands for.
cut = _sliced if JIT_DISABLED else _cut
