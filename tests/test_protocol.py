"""The Pool protocol command (``agents.protocol``): its table for a rack where the
ghost-ball player fouls and the planner runs out, and its bookkeeping (a run-out is a
clearance, a break-and-run a run-out)."""

from __future__ import annotations

import gymnasium as gym
import pytest
from agents import protocol


def test_the_table_scores_the_rack_as_played(capsys):
    protocol.main(["--policies", "ghost", "planner", "--episodes", "1", "--seed", "1001",
                   "--candidates", "64"])  # fmt: skip
    out = capsys.readouterr().out
    rows = {line.split()[0]: line.split() for line in out.splitlines()[3:]}
    ghost, planner = rows["ghost"], rows["planner"]
    # name, reward ("mean ± std": 3 cells), pot rate, foul rate, cleared, run-out,
    # break-and-run, shots, ms
    assert float(ghost[5]) > 0 and ghost[7] == "0/1"  # it fouled: no run-out
    assert planner[5] == "0.000" and planner[6] == planner[7] == planner[8] == "1/1"
    assert float(planner[1]) == 15.0


def test_run_outs_are_clearances_and_break_and_runs_run_outs():
    env = gym.make("Pool2D-v0", max_episode_steps=protocol.MAX_SHOTS)
    for name in protocol.POLICIES:
        record = protocol.Record()
        policy = protocol.make_policy(name, env, 0, 32)
        for seed in (1000, 1001):
            protocol.play(env, policy, seed, record)
        assert record.cleared >= record.run_outs >= record.break_and_runs
        assert record.potting_shots <= record.shots <= 2 * protocol.MAX_SHOTS
        assert record.fouls <= record.shots


def test_no_episodes_is_refused():
    with pytest.raises(SystemExit):
        protocol.main(["--episodes", "0"])


def test_the_slingshot_table(capsys):
    protocol.main(["--game", "slingshot", "--level", "handmade", "--episodes", "1",
                   "--policies", "ballistic", "planner", "--candidates", "24"])  # fmt: skip
    out = capsys.readouterr().out
    rows = {line.split()[0]: line.split() for line in out.splitlines()[3:]}
    assert set(rows) == {"ballistic", "planner"}
    for row in rows.values():  # reward (3 cells), cleared, pigs a launch, launches, ms
        assert row[4] in ("0/1", "1/1") and float(row[6]) >= 1.0


def test_a_policy_of_the_other_game_is_refused():
    with pytest.raises(SystemExit):
        protocol.main(["--game", "slingshot", "--policies", "ghost"])
