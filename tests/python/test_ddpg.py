"""swarmcl.rl's DDPG with RAG (Algorithm 1; issue 15 item 6): networks,
updates, the protected replay buffer, checkpoints that resume bit for bit,
the policy export (helpers' policy-mlp/1 contract) and the CLI."""

import json
import os
import struct
import subprocess
import sys

import numpy as np
import pytest

if os.environ.get("SWARMCL_REQUIRE_RL") == "1":
    import torch  # scripts/test.sh installs swarmcl[rl]
else:
    torch = pytest.importorskip("torch")
pytest.importorskip("gymnasium")
pytest.importorskip("safetensors")

from swarmcl.rl.ddpg import DDPG, Actor, Critic, DDPGConfig, ReplayBuffer, obs_scale  # noqa: E402
from swarmcl.rl.export import load_policy, policy_actions  # noqa: E402
from swarmcl.rl.train import TrainConfig, Trainer  # noqa: E402

from conftest import REPO  # noqa: E402


@pytest.fixture(autouse=True)
def _one_thread():
    n = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(n)


def tiny(rag=True, **kw):
    t = dict(worlds=2, agents=4, max_steps=10, episodes_per_leader=2, rag=rag, seed=3, leader_turn_every=4)
    t.update(kw)
    return TrainConfig(**t), DDPGConfig(buffer_size=100, batch_size=16)


def test_networks_have_the_papers_shapes():
    a, c = Actor(54), Critic(54)
    assert [tuple(l.weight.shape) for l in a.net] == [(128, 54), (256, 128), (64, 256), (4, 64)]
    assert [tuple(l.weight.shape) for l in c.net] == [(128, 58), (256, 128), (64, 256), (1, 64)]
    assert a.activations() == ["relu", "relu", "linear", "tanh"]
    x = torch.randn(7, 54) * 50
    y = a(x)
    assert y.shape == (7, 4) and float(y.detach().abs().max()) <= 1.0
    assert c(x, y).shape == (7,)
    d = DDPGConfig()
    assert (d.lr_actor, d.lr_critic, d.gamma, d.buffer_size, d.batch_size, d.tau, d.noise) == \
        (1e-4, 1e-3, 0.98, 10_000, 300, 1e-3, 0.05)  # Table 1
    t = TrainConfig()
    assert (t.max_steps, t.episodes_per_leader) == (1200, 500)


def test_an_update_moves_the_networks_and_the_targets_by_tau():
    torch.manual_seed(0)
    agent = DDPG(54, DDPGConfig(batch_size=8), obs_std=obs_scale(54))
    rng = np.random.default_rng(0)
    batch = (rng.normal(size=(8, 54)).astype(np.float32), rng.uniform(-1, 1, (8, 4)).astype(np.float32),
             rng.normal(size=8).astype(np.float32), rng.normal(size=(8, 54)).astype(np.float32),
             np.zeros(8, np.float32))
    before = {k: v.clone() for k, v in agent.actor.state_dict().items()}
    tgt_before = {k: v.clone() for k, v in agent.actor_target.state_dict().items()}
    out = agent.update(batch)
    assert np.isfinite(out["critic_loss"]) and np.isfinite(out["actor_loss"])
    after = agent.actor.state_dict()
    for k in ("net.0.weight", "net.3.bias"):
        assert not torch.equal(before[k], after[k])
        expect = (1 - 1e-3) * tgt_before[k] + 1e-3 * after[k]
        torch.testing.assert_close(agent.actor_target.state_dict()[k], expect, rtol=0, atol=1e-7)


def _batch(rng, n=8, protected=0.0):
    return (rng.normal(size=(n, 54)).astype(np.float32), rng.uniform(-1, 1, (n, 4)).astype(np.float32),
            rng.normal(size=n).astype(np.float32), rng.normal(size=(n, 54)).astype(np.float32),
            np.zeros(n, np.float32), np.full(n, protected, np.float32))


def test_ours_options_actor_delay_bc_and_init():
    """The options that are ours, not the paper's: the DDPG-paper init of the
    last layers, critic-only warm-up, behaviour cloning on protected rows."""
    torch.manual_seed(1)
    agent = DDPG(54, DDPGConfig(batch_size=8, actor_delay=2))
    assert float(agent.actor.net[-1].weight.detach().abs().max()) <= 3e-3
    assert float(agent.critic.net[-1].weight.detach().abs().max()) <= 3e-3
    rng = np.random.default_rng(2)
    w0 = agent.actor.net[0].weight.clone()
    c0 = agent.critic.net[0].weight.clone()
    agent.update(_batch(rng))
    agent.update(_batch(rng))
    assert torch.equal(agent.actor.net[0].weight, w0) and not torch.equal(agent.critic.net[0].weight, c0)
    agent.update(_batch(rng))
    assert not torch.equal(agent.actor.net[0].weight, w0)
    # A large BC weight pulls the actor towards the protected rows' actions.
    torch.manual_seed(1)
    bc = DDPG(54, DDPGConfig(batch_size=8, bc_weight=100.0, lr_actor=1e-3))
    batch = _batch(rng, 32, protected=1.0)
    err = lambda: float(((bc.act(batch[0]) - batch[1]) ** 2).mean())  # noqa: E731
    before = err()
    for _ in range(100):
        bc.update(batch)
    assert err() < 0.5 * before
    # Unprotected rows: the BC term is 0 (the no-RAG run is plain DDPG).
    torch.manual_seed(1)
    plain = DDPG(54, DDPGConfig(batch_size=8))
    torch.manual_seed(1)
    nobc = DDPG(54, DDPGConfig(batch_size=8, bc_weight=100.0))
    b0 = _batch(rng, 8, protected=0.0)
    plain.update(b0)
    nobc.update(b0)
    assert torch.equal(plain.actor.net[0].weight, nobc.actor.net[0].weight)


def _rows(n, start=0, d=3):
    v = np.arange(start, start + n, dtype=np.float32)
    return (np.repeat(v[:, None], d, 1), np.repeat(v[:, None], 4, 1), v, v[:, None].repeat(d, 1), 0 * v)


def test_replay_buffer_protection_flags():
    b = ReplayBuffer(10, 3)
    assert b.add(*_rows(6, 0), protect=True) == 6
    # Unprotected rows take only the 4 open slots; the rest are dropped.
    assert b.add(*_rows(8, 100), protect=False) == 4
    assert b.dropped == 4 and len(b) == 10 and b.protected.sum() == 6
    assert sorted(b.rew[b.protected]) == list(range(6))
    assert sorted(b.rew[~b.protected]) == [104, 105, 106, 107]   # the batch's last rows
    # More unprotected rows replace the oldest unprotected ones only.
    assert b.add(*_rows(2, 200), protect=False) == 2
    assert sorted(b.rew[~b.protected]) == [106, 107, 200, 201]
    # Algorithm 1 line 9: flags cleared, then anything may be overwritten, oldest first.
    b.clear_protection()
    assert b.add(*_rows(3, 300), protect=False) == 3
    assert 0 not in b.rew and 1 not in b.rew and 2 not in b.rew and 3 in b.rew
    # A protected write takes unprotected slots first (oldest first).
    assert b.add(*_rows(4, 400), protect=True) == 4
    assert sorted(b.rew[b.protected]) == [400, 401, 402, 403]
    # ... and when everything is protected, the oldest protected.
    assert b.add(*_rows(10, 500), protect=True) == 10 and b.protected.all()
    assert b.add(*_rows(3, 600), protect=False) == 0
    rng = np.random.default_rng(1)
    s, a, r, s2, d, f = b.sample(rng, 5)
    assert s.shape == (5, 3) and a.shape == (5, 4) and r.shape == (5,) and s2.shape == (5, 3)
    assert f.dtype == np.float32 and np.all(f == 1)


def test_replay_buffer_protected_cap():
    b = ReplayBuffer(10, 3, max_protected_fraction=0.5)
    assert b.add(*_rows(8, 0), protect=True) == 5 and b.protected.sum() == 5
    assert b.add(*_rows(8, 100), protect=False) == 5 and b.protected.sum() == 5
    assert b.add(*_rows(2, 200), protect=True) == 2 and b.protected.sum() == 5
    with pytest.raises(ValueError, match="size"):
        ReplayBuffer(0, 3)
    with pytest.raises(ValueError, match="max_protected_fraction"):
        ReplayBuffer(10, 3, max_protected_fraction=1.5)


def test_rag_seeds_the_buffer_once_per_leader(ctx):
    tc, dc = tiny(rag=True)
    t = Trainer(ctx, tc, dc)
    try:
        rec = t.train_episode()                 # episode 0: leader change, RAG, protected
        assert rec["rag"] and rec["protected"] == 80 and rec["buffer"] == 80
        # The stored actions are the RAG's, in the actor's units: the first
        # step's rows equal rag_actions() at the episode's start.
        t.env.reset(t._leader_key(0))
        t.env.set_leader_controls(t._leader_plan(t._leader_key(0))[0])
        first = np.clip(t.env.rag_actions() / t.scale, -1, 1)
        np.testing.assert_array_equal(t.buffer.act[:8], first)
        rec = t.train_episode()                 # episode 1: actor + noise, 20 open slots
        assert not rec["rag"] and rec["protected"] == 80 and rec["buffer"] == 100
        # The actor's 80 rows cycle through the 20 unprotected slots: the last 20 stay.
        st = t.buffer.stamp[~t.buffer.protected]
        assert sorted(st) == list(range(140, 160)) and t.buffer.dropped == 0
        rec = t.train_episode()                 # episode 2: new leader: flags cleared, RAG again
        assert rec["rag"] and rec["protected"] == 80
        assert t.agent.updates == 30 - 1         # an update every step once the buffer holds a batch
    finally:
        t.close()
    tc, dc = tiny(rag=False)
    t = Trainer(ctx, tc, dc)
    try:
        for _ in range(3):
            rec = t.train_episode()
            assert not rec["rag"] and rec["protected"] == 0
    finally:
        t.close()


def _same_state(a: Trainer, b: Trainer):
    for k in ("actor", "critic", "actor_target", "critic_target"):
        sa, sb = getattr(a.agent, k).state_dict(), getattr(b.agent, k).state_dict()
        for name in sa:
            assert torch.equal(sa[name], sb[name]), f"{k}.{name}"
    oa, ob = a.agent.actor_opt.state_dict()["state"], b.agent.actor_opt.state_dict()["state"]
    for i in oa:
        assert torch.equal(oa[i]["exp_avg"], ob[i]["exp_avg"])
    for k in ("obs", "act", "rew", "protected", "stamp"):
        assert np.array_equal(getattr(a.buffer, k), getattr(b.buffer, k)), k
    assert a.rng.bit_generator.state == b.rng.bit_generator.state
    assert [h["mean_reward"] for h in a.history] == [h["mean_reward"] for h in b.history]
    assert a.agent.updates == b.agent.updates and a.episode == b.episode


def test_resumed_training_equals_uninterrupted(ctx, tmp_path):
    tc, dc = tiny(rag=True)
    whole = Trainer(ctx, tc, dc)
    whole.train(episodes=4)
    part = Trainer(ctx, tc, dc)
    ckpt = str(tmp_path / "run.ckpt")
    part.train(episodes=3, checkpoint=ckpt)     # stops inside a leader's K episodes
    part.close()
    resumed = Trainer.load(ctx, ckpt)
    assert resumed.episode == 3
    resumed.train(episodes=4)
    try:
        _same_state(whole, resumed)
    finally:
        whole.close()
        resumed.close()
    (tmp_path / "junk.ckpt").write_bytes(b"not a checkpoint")
    with pytest.raises(Exception):
        Trainer.load(ctx, str(tmp_path / "junk.ckpt"))


def test_export_follows_the_policy_contract(ctx, tmp_path):
    tc, dc = tiny(rag=True)
    t = Trainer(ctx, tc, dc)
    try:
        t.train(episodes=1)
        path = tmp_path / "policy.safetensors"
        t.export(str(path))
        obs = t.env.reset(5)
        expect = t.agent.act(obs) * t.scale
    finally:
        t.close()
    raw = path.read_bytes()
    n = struct.unpack("<Q", raw[:8])[0]
    header = json.loads(raw[8:8 + n])
    meta = header.pop("__metadata__")
    assert meta["swarmcl.format"] == "policy-mlp/1"
    assert meta["swarmcl.activations"] == "relu,relu,linear,tanh"
    assert meta["swarmcl.efs"] == "1"
    scale = [float(v) for v in meta["swarmcl.action_scale"].split(",")]
    np.testing.assert_allclose(scale, [0.1, 0.0698, 0.0698, 0.0698], atol=1e-4)
    assert json.loads(meta["swarmcl.env"])["scenario"] == "roaming" and "ddpg+rag" in meta["swarmcl.trained_by"]
    shapes = {"layers.0": [128, 54], "layers.1": [256, 128], "layers.2": [64, 256], "layers.3": [4, 64]}
    for layer, (o, i) in shapes.items():
        assert header[f"{layer}.weight"]["shape"] == [o, i] and header[f"{layer}.bias"]["shape"] == [o]
    assert header["obs_mean"]["shape"] == [54] and header["obs_std"]["shape"] == [54]
    assert all(e["dtype"] == "F32" for e in header.values())
    ends = sorted(tuple(e["data_offsets"]) for e in header.values())
    assert ends[0][0] == 0 and all(a[1] == b[0] for a, b in zip(ends, ends[1:])) and ends[-1][1] == len(raw) - 8 - n
    policy = load_policy(path)
    assert (policy["obs_std"] > 0).all()
    # NumPy inference from the file = the trained actor in env units.
    np.testing.assert_allclose(policy_actions(policy, obs), expect, rtol=1e-5, atol=1e-6)


def test_cli_trains_resumes_and_exports(tmp_path):
    env = dict(os.environ, PYTHONPATH=str(REPO / "bindings/python") + os.pathsep + os.environ.get("PYTHONPATH", ""))
    ckpt, model, out = tmp_path / "c.ckpt", tmp_path / "p.safetensors", tmp_path / "r.json"
    base = [sys.executable, "-m", "swarmcl.rl", "train", "--worlds", "2", "--agents", "3", "--max-steps", "8",
            "--episodes-per-leader", "2", "--buffer-size", "64", "--batch-size", "8", "--checkpoint", str(ckpt),
            "--quiet"]
    subprocess.run(base + ["--episodes", "2"], env=env, check=True, timeout=120)
    r = subprocess.run(base + ["--resume", "--episodes", "3", "--export", str(model), "--json", str(out)],
                       env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    rec = json.loads(out.read_text())
    assert len(rec["episodes"]) == 3 and [e["rag"] for e in rec["episodes"]] == [True, False, True]
    assert load_policy(model)["metadata"]["swarmcl.format"] == "policy-mlp/1"
    r = subprocess.run(base[:4] + ["--resume", "--checkpoint", str(tmp_path / "missing.ckpt"), "--episodes", "1"],
                       env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 2 and "--resume needs an existing --checkpoint" in r.stderr
