"""Torch's CPU kernels named, not picked for the CPU: training that repeats across machines.

The engine's results do not depend on the machine's instruction set, and neither do
numpy's here. torch's do. ATen picks vectorised kernels for the CPU it finds (AVX2,
AVX-512, ...), and oneMKL, which does torch's matrix products on x86, picks its code path
by CPU too. Each path rounds in its own order, and over thousands of PPO updates two
machines' runs part (``bench/reproducibility.py`` measures each of these switches).
Both libraries take a name instead:

* ``ATEN_CPU_CAPABILITY=avx2``: ATen's AVX2 kernels, also on an AVX-512 CPU;
* ``MKL_CBWR=AVX2``: oneMKL's conditional numerical reproducibility, which gives the same
  results on every CPU that has AVX2, for the same MKL version and thread count.

Threads round too. torch's thread count is OpenMP's, and the engine's numba threads are
OpenMP's as well: each batched step sets OpenMP to the engine's thread count (every core
by default), and torch then follows it, so the same run on a 4-core machine would do
its updates on 4 threads. ``one_torch_thread()`` sets torch back to one thread;
``agents.train`` calls it after every env step (``OneTorchThread``) and the evaluation
before every action.

``pin_torch_kernels`` sets both, before torch is imported, on x86-64 CPUs with AVX2 and
FMA. It does nothing elsewhere (ARM, older x86, or torch already loaded), and it says so
in what it returns. Values already in the environment win, so ``MKL_CBWR=AUTO`` on the
command line opts out.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
from pathlib import Path
from typing import Any

__all__ = [
    "PINNED",
    "add_kernels_option",
    "hold_torch_threads",
    "one_torch_thread",
    "pin_torch_kernels",
    "x86_with_avx2",
]

PINNED = {"ATEN_CPU_CAPABILITY": "avx2", "MKL_CBWR": "AVX2"}


def x86_with_avx2(cpuinfo: Path = Path("/proc/cpuinfo")) -> bool:
    """Whether this is an x86-64 CPU with AVX2 and FMA (read from Linux's cpuinfo; other
    systems count as without, so nothing is forced on a CPU that may lack them)."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return False
    try:
        text = cpuinfo.read_text()
    except OSError:
        return False
    for line in text.splitlines():
        if line.startswith("flags"):
            flags = set(line.partition(":")[2].split())
            return {"avx2", "fma"} <= flags
    return False


def pin_torch_kernels() -> dict[str, str]:
    """Name torch's CPU kernels (``PINNED``) for this process and its children. Returns
    the settings in force, or ``{"not pinned": why}`` where they cannot apply."""
    if "torch" in sys.modules:
        return {"not pinned": "torch was imported before the kernels could be named"}
    if not x86_with_avx2():
        return {"not pinned": "not an x86-64 CPU with AVX2 and FMA"}
    for name, value in PINNED.items():
        os.environ.setdefault(name, value)
    return {name: os.environ[name] for name in PINNED}


def add_kernels_option(parser: argparse.ArgumentParser) -> None:
    """``--portable-kernels`` / ``--no-portable-kernels`` (default on), for the commands."""
    parser.add_argument(
        "--portable-kernels",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="name torch's CPU kernels (AVX2) so that runs repeat bitwise on other x86 "
        "machines (default on; agents/_kernels.py)",
    )


def hold_torch_threads(threads: int = 1) -> None:
    """torch on ``threads`` threads again (an engine step may have set OpenMP to every
    core)."""
    import torch

    if torch.get_num_threads() != threads:
        torch.set_num_threads(threads)


def one_torch_thread() -> None:
    """torch on one thread again (``hold_torch_threads(1)``)."""
    hold_torch_threads(1)


def torch_thread_callback(threads: int = 1) -> Any:
    """An SB3 callback that keeps torch on ``threads`` threads (default one) after every
    env step, so that the policy's forward passes and the updates run as on any machine.
    (``agents.train --torch-threads 2`` is one of the rounding variants of the
    reproducibility check in docs/training.md.)"""
    from stable_baselines3.common.callbacks import BaseCallback

    class HoldTorchThreads(BaseCallback):
        def _on_training_start(self) -> None:
            hold_torch_threads(threads)

        def _on_step(self) -> bool:
            hold_torch_threads(threads)
            return True

        def _on_rollout_end(self) -> None:
            hold_torch_threads(threads)

    return HoldTorchThreads()
