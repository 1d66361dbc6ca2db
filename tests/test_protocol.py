"""The protocol command (``agents.protocol``): the Pool table for a rack where the
ghost-ball player fouls and the planner runs out, and its bookkeeping (a run-out is a
clearance, a break-and-run a run-out); the Slingshot tables; the template tasks'
attempts, success@k and AUCCESS; a trained agent's row."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
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
    for name in ("random", "ghost", "planner"):  # the agent: test_a_trained_agent_...
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


# -- Slingshot templates: PHYRE's attempts, success@k and AUCCESS ------------------------------
def test_auccess_is_phyres_weighted_area():
    """AUCCESS = sum_k w_k s_k / sum_k w_k, w_k = log(k + 1) - log(k): worked by hand for
    two attempts (w_1 = log 2, w_2 = log 3 - log 2, sum log 3)."""
    assert protocol.auccess([1, 1, 1], 10) == pytest.approx(1.0)
    assert protocol.auccess([0, 0], 10) == 0.0
    # tasks solved at attempts 1 and 2, one never: s_1 = 1/3, s_2 = 2/3
    expected = (np.log(2) / 3 + (np.log(3) - np.log(2)) * 2 / 3) / np.log(3)
    assert protocol.auccess([1, 2, 0], 2) == pytest.approx(expected)
    # solving later counts less: the same success@10, lower AUCCESS
    assert protocol.auccess([1, 0], 10) > protocol.auccess([10, 0], 10) > 0


def test_a_task_stops_at_its_first_success():
    env = gym.make("Slingshot2D-v0", level="templates", templates=["tower"], num_levels=1,
                   start_level=3, num_birds=1)  # fmt: skip
    record = protocol.AttemptRecord(attempts=5)
    planner = protocol.make_policy("planner", env, 0, 32)
    calls = []

    def two_duds_then_the_planner(obs):  # a dud lands 3 m from the sling: no damage
        calls.append(obs)
        return np.array([-1.0, -1.0], np.float32) if len(calls) <= 2 else planner(obs)

    protocol.play_task(env, two_duds_then_the_planner, "tower", 0, record)
    assert record.solved_at == [3] and record.launches == 3 and record.first_rewards == [0.0]
    assert record.success(2) == 0.0 and record.success(3) == record.success(5) == 1.0


def test_the_template_table(capsys):
    protocol.main(["--game", "slingshot", "--level", "templates", "--split", "held-out",
                   "--episodes", "3", "--attempts", "2", "--policies", "ballistic", "planner",
                   "--candidates", "48"])  # fmt: skip
    out = capsys.readouterr().out.splitlines()
    assert (
        "split held-out (wall, castle, stairs)" in out[0]
        and "level seeds 1000000-1000002" in out[0]
    )
    rows = {line.split()[0]: line.split() for line in out[3:5]}
    ballistic, planner = rows["ballistic"], rows["planner"]
    # deterministic: success@2 = success@1; the planner clears what it simulates
    assert ballistic[1] == ballistic[2] and float(planner[2]) >= float(planner[1]) > 0.5
    assert out[7].split() == ["policy", "wall", "castle", "stairs"]


@pytest.mark.parametrize(
    "argv",
    [
        ["--game", "slingshot", "--level", "templates", "--attempts", "0"],
        ["--policies", "agent"],  # no --model
        ["--policies", "ghost", "--model", "runs/x"],  # --model without the agent
    ],
)
def test_bad_protocol_options_are_refused(argv):
    with pytest.raises(SystemExit):
        protocol.main(argv)


def test_a_trained_agent_plays_its_own_task_and_no_other(tmp_path):
    """--model must have trained on a task of the chosen game (its observations and
    actions are that task's)."""
    from agents import train

    run = tmp_path / "run"
    train.main(["--env", "Slingshot2DCallShot-v0", "--timesteps", "32", "--num-envs", "4",
                "--run-dir", str(run), "--no-progress-bar", "--no-evaluate", "--hyperparams",
                "n_steps=8", "batch_size=32", "n_epochs=1"])  # fmt: skip
    wanted = "Pool2DRackBestShots-v0 or Pool2DRackCallShot-v0"
    message = f"--model must be a run trained on {wanted}, got one trained on Slingshot2DCallShot"
    with pytest.raises(ValueError, match=message):
        protocol.main(["--policies", "agent", "--model", str(run), "--episodes", "1"])
    protocol.main(["--game", "slingshot", "--level", "handmade", "--policies", "agent",
                   "--model", str(run), "--episodes", "1"])  # fmt: skip
    # On a Slingshot env the agent's first call is its deterministic action and later ones
    # are sampled (retries at a task explore); on Pool every call is deterministic.
    agent = protocol.load_agent(str(run), ("Slingshot2DCallShot-v0",))
    env = protocol._make_env("agent", "Slingshot2D-v0", agent, {"level": "table"})
    policy = protocol.make_policy("agent", env, 0, 8, agent)
    obs, _ = env.reset(seed=0)
    first, later = policy(obs), [policy(obs) for _ in range(3)]
    expected, _ = agent.model.predict(obs[None], deterministic=True)
    np.testing.assert_array_equal(first, expected[0])
    assert all(not np.array_equal(first, a) for a in later)
    with pytest.raises(SystemExit):  # a mean over training seeds needs different seeds
        protocol.main(["--game", "slingshot", "--level", "handmade", "--policies", "agent",
                       "--model", str(run), str(run), "--episodes", "1"])  # fmt: skip


def test_the_mean_over_seeds_row_is_the_mean_and_std_of_the_rows():
    a, b = protocol.Record(), protocol.Record()
    a.rewards, a.shots, a.potting_shots, a.fouls, a.cleared = [14.0, 15.0], 40, 30, 2, 2
    b.rewards, b.shots, b.potting_shots, b.fouls, b.cleared = [12.0, 13.0], 50, 30, 5, 1
    row = protocol.seeds_row("agent, 2 seeds", [a, b])
    assert row[0] == "agent, 2 seeds" and len(row) == len(protocol.POOL_HEADER)
    assert row[1] == "13.500 ± 1.000"  # rewards 14.5 and 12.5
    assert row[3] == "0.075 ± 0.025"  # fouls a shot 0.05 and 0.10
    assert row[4] == "0.750 ± 0.250"  # racks cleared: 2 of 2 and 1 of 2


def test_the_constant_calls_table_lists_the_best_blind_players(capsys):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "bench" / "constant_calls.py"
    spec = importlib.util.spec_from_file_location("constant_calls", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    module.main(["--env", "Pool2DCallShot-v0", "--episodes", "6", "--speeds", "-0.6", "0.9",
                 "--top", "12"])  # fmt: skip
    lines = capsys.readouterr().out.splitlines()
    rows = [line.split("|") for line in lines[3:]]
    assert len(rows) == 12  # six pockets x two speeds, best first
    rewards = [float(row[3].split("±")[0]) for row in rows]
    assert rewards == sorted(rewards, reverse=True)
    # low in the speed window beats far above it for the same pocket, on average
    by = {(row[1].strip(), row[2].strip()): r for row, r in zip(rows, rewards, strict=True)}
    low = np.mean([by[(str(p), "-0.6")] for p in range(6)])
    high = np.mean([by[(str(p), "+0.9")] for p in range(6)])
    assert low > high
