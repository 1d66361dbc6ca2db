"""Torch's CPU kernels named for repeatable training (agents/_kernels.py): the CPU check,
the environment the commands set, and what a run records."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from agents import _kernels

ROOT = Path(__file__).resolve().parents[1]
FLAGS = "flags\t\t: fpu sse sse2 ssse3 sse4_1 sse4_2 avx"


def test_the_cpu_check_reads_avx2_and_fma_from_cpuinfo(tmp_path, monkeypatch):
    monkeypatch.setattr(_kernels.platform, "machine", lambda: "x86_64")
    cpuinfo = tmp_path / "cpuinfo"
    cpuinfo.write_text(f"processor\t: 0\n{FLAGS} avx2 fma bmi2\n")
    assert _kernels.x86_with_avx2(cpuinfo)
    cpuinfo.write_text(f"processor\t: 0\n{FLAGS} fma\n")  # no AVX2
    assert not _kernels.x86_with_avx2(cpuinfo)
    assert not _kernels.x86_with_avx2(tmp_path / "missing")
    monkeypatch.setattr(_kernels.platform, "machine", lambda: "aarch64")
    cpuinfo.write_text(f"{FLAGS} avx2 fma\n")
    assert not _kernels.x86_with_avx2(cpuinfo)


def test_too_late_once_torch_is_loaded():
    import torch  # noqa: F401

    before = dict(os.environ)
    assert "not pinned" in _kernels.pin_torch_kernels()
    assert dict(os.environ) == before


def _train(tmp_path: Path, *flags: str, env: dict[str, str] | None = None) -> dict:
    child = {k: v for k, v in os.environ.items() if k not in _kernels.PINNED}
    child.update(env or {})
    run_dir = tmp_path / "run"
    done = subprocess.run(
        [sys.executable, "-m", "agents.train", "--timesteps", "32", "--num-envs", "4",
         "--run-dir", str(run_dir), "--env-kwargs", '{"max_shot_seconds": 2.0}',
         "--no-evaluate", "--no-progress-bar",
         "--hyperparams", "n_steps=8", "batch_size=16", "n_epochs=1", *flags],
        cwd=ROOT, env=child, capture_output=True, text=True, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads((run_dir / "training.json").read_text())["torch_kernels"]


@pytest.mark.skipif(not _kernels.x86_with_avx2(), reason="needs an x86-64 CPU with AVX2")
def test_the_training_command_names_the_kernels_and_records_them(tmp_path):
    kernels = _train(tmp_path / "pinned")
    assert kernels["MKL_CBWR"] == "AVX2" and kernels["ATEN_CPU_CAPABILITY"] == "avx2"
    assert kernels["aten_kernels"] == "AVX2" and kernels["threads"] == 1
    assert _train(tmp_path / "free", "--no-portable-kernels")["MKL_CBWR"] is None
    # What the user set wins.
    assert _train(tmp_path / "own", env={"MKL_CBWR": "AUTO"})["MKL_CBWR"] == "AUTO"
