"""Compiled kernels that travel with the package, so a fresh install's first step does
not wait for the compiler.

numba caches a compiled kernel under a key of its signature, its bytecode and the CPU it
was compiled for (``codegen.magic_tuple()``: the target triple, the CPU's name and its
feature flags), and loads it only into a process whose key is the same. A kernel
compiled on one CPU is therefore never found on another, even when its code would run
there. The wheel ships kernels compiled for *portable* CPU targets instead (``TARGETS``:
the x86-64 micro-architecture levels, code any CPU of that level runs), in the folder
``_kernels`` beside the kernel modules, and ``KernelCache`` looks them up when this CPU's
own cache misses:

1. this CPU's own compile, where numba always looks (``__pycache__``, ``NUMBA_CACHE_DIR``
   or the user's cache folder; ``_jit.choose_cache_dir``): what ``impulse2d-compile``
   and every compile on this machine write, tuned to this CPU, so it wins when present;
2. then each portable target this CPU can run, best first, in that cache and in the
   shipped folder.

The shipped folder is used only when it was built from these very sources, by this
numba and this Python (``MANIFEST``, checked once a process). Otherwise, or on a CPU no
shipped target fits (not x86-64, or an x86-64 without SSE2's successors the levels need:
only ``generic`` then), or where ``IMPULSE2D_SHIPPED_KERNELS=0``, each kernel compiles
once, as without it, and is cached for later runs.

Why levels and not the build machine's CPU: the wheel is built once (CI) and installed
on any x86-64. ``x86-64-v3`` (AVX2, FMA, BMI: every x86-64 CPU since about 2015) runs
the box stacks' lane loops about as fast as code tuned for the CPU; ``generic`` (SSE2)
is 1.2x slower there and is the fallback for older CPUs (``docs`` speed page). The
results are the same bits whichever target ran them: the kernels are compiled without
``fastmath``, so LLVM neither contracts ``a * b + c`` into an FMA nor reorders sums, on
any target (a test compares the states).

``python -m impulse2d.compile --ship`` builds the folder (CI does before building the
wheel; ``ship``).
"""

from __future__ import annotations

import functools
import json
import os
import platform
import sys
from pathlib import Path
from typing import Any

import numba
from numba.core.caching import FunctionCache, IndexDataCacheFile

SHIPPED = Path(__file__).parent / "_kernels"
MANIFEST = "manifest.json"
SWITCH = "IMPULSE2D_SHIPPED_KERNELS"  # "0": never load portable kernels

# The portable targets, best first: (LLVM CPU name, the host features it needs). A level's
# features are those LLVM's x86-64-vN adds over SSE2 (the psABI's levels), in LLVM's
# spelling of ``llvmlite.binding.get_host_cpu_features``.
_V2 = ("cx16", "popcnt", "sse3", "sse4.1", "sse4.2", "ssse3", "sahf")
_V3 = (*_V2, "avx", "avx2", "bmi", "bmi2", "f16c", "fma", "lzcnt", "movbe", "xsave")
TARGETS: tuple[tuple[str, tuple[str, ...]], ...] = (("x86-64-v3", _V3), ("generic", ()))


def enabled() -> bool:
    """Whether portable kernels may be loaded (``IMPULSE2D_SHIPPED_KERNELS`` is not 0)."""
    return os.environ.get(SWITCH, "").strip() != "0"


def build_facts(digest: str) -> dict[str, Any]:
    """What the shipped kernels must match to be loaded: these sources (``digest``, the
    hash ``_jit.kernel_sources_digest`` gives), this numba and this Python."""
    return {
        "sources": digest,
        "numba": numba.__version__,
        "python": f"{sys.version_info[0]}.{sys.version_info[1]}",
        "machine": platform.machine(),
    }


@functools.cache
def shipped_folder() -> Path | None:
    """The shipped kernels' folder, when it fits this process (else None)."""
    from ._jit import _PACKAGE, kernel_sources_digest

    try:
        built = json.loads((SHIPPED / MANIFEST).read_text())
    except (OSError, ValueError):
        return None
    wanted = build_facts(kernel_sources_digest(_PACKAGE))
    return SHIPPED if all(built.get(k) == v for k, v in wanted.items()) else None


@functools.cache
def _host_features() -> frozenset[str]:
    from llvmlite import binding

    flags = binding.get_host_cpu_features()
    return frozenset(name for name, on in flags.items() if on)


def runnable_targets(triple: str) -> list[str]:
    """The portable targets this CPU runs, best first (none off x86-64)."""
    if not triple.startswith("x86_64"):
        return []
    have = _host_features()
    return [name for name, needs in TARGETS if have.issuperset(needs)]


class KernelCache(FunctionCache):
    """numba's cache of one kernel, which also finds a portable compile of it (this
    module's docstring): this CPU's own first, then each portable target, best first."""

    def __init__(self, py_func: Any) -> None:
        super().__init__(py_func)
        folder = shipped_folder()
        self._shipped = None
        self.loaded: dict[Any, str] = {}  # signature -> the portable target loaded for it
        if folder is not None:
            stamp = self._cache_file._source_stamp
            self._shipped = IndexDataCacheFile(str(folder), self._impl.filename_base, stamp)

    def portable_keys(self, sig: Any, codegen: Any) -> list[tuple[Any, ...]]:
        """The index keys of this kernel's portable compiles this CPU can run."""
        signature, (triple, _, _), code = self._index_key(sig, codegen)
        return [(signature, (triple, cpu, ""), code) for cpu in runnable_targets(triple)]

    def _load_overload(self, sig: Any, target_context: Any) -> Any:
        data = super()._load_overload(sig, target_context)
        if data is not None or not self._enabled or not enabled():
            return data
        for key in self.portable_keys(sig, target_context.codegen()):
            for file in self._files():
                found = file.load(key)
                if found is not None:
                    self.loaded[sig] = key[1][1]
                    return self._impl.rebuild(target_context, found)
        return None

    def _files(self) -> list[IndexDataCacheFile]:
        return [self._cache_file] if self._shipped is None else [self._cache_file, self._shipped]

    def holds_any(self, codegen: Any) -> bool:
        """Whether some compile of this kernel would load here, for any signature."""
        files = self._files() if enabled() else [self._cache_file]
        for file in files:
            index = file._load_index()  # {} when missing or stale
            for signature, *_ in index:
                keys = [self._index_key(signature, codegen)]
                if enabled():
                    keys += self.portable_keys(signature, codegen)
                if any(key in index for key in keys):
                    return True
        return False


def portable(dispatcher: Any) -> Any:
    """Give a compiled kernel ``KernelCache`` in place of numba's (``_jit.kernel``)."""
    if isinstance(getattr(dispatcher, "_cache", None), FunctionCache):
        dispatcher._cache = KernelCache(dispatcher.py_func)
    return dispatcher
